// Reading a scene file (TOML) into a Scene: parse, apply --set overrides, validate every key,
// load referenced models, build the camera. Errors are SceneError (file:line:col: key: message).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace anamorph {

// `overrides` are "dotted.key=value" strings; the value is TOML (a bare word is taken as a
// string), e.g. "camera.fov=90", "camera.preset=fisheye", "image.width=320".
// `frame` evaluates the scene's [[animate]] keys (before the overrides, which win).
Scene load_scene(const std::filesystem::path& file, const std::vector<std::string>& overrides = {},
                 double frame = 0);

// Same, from TOML text (`name` is used in messages and to resolve relative paths).
Scene load_scene_from_string(const std::string& text, const std::filesystem::path& name,
                             const std::vector<std::string>& overrides = {}, double frame = 0);

}  // namespace anamorph
