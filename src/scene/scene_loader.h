// Reading a scene file (TOML) into a Scene: parse, apply --set overrides, validate every key,
// load referenced models, build the camera. Errors are SceneError (file:line:col: key: message).
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace anamorph {

// `overrides` are "dotted.key=value" strings; the value is TOML (a bare word is taken as a
// string), e.g. "camera.fov=90", "camera.preset=fisheye", "image.width=320".
// `frame` evaluates the scene's [[animate]] keys (before the overrides, which win).
Scene load_scene(const std::filesystem::path& file, const std::vector<std::string>& overrides = {},
                 double frame = 0);

// Same, from TOML text (`name` is used in messages and to resolve relative paths and includes).
Scene load_scene_from_string(const std::string& text, const std::filesystem::path& name,
                             const std::vector<std::string>& overrides = {}, double frame = 0);

// Whether every [[animate]] key of `s` lies under camera, image or render: then the frames
// differ only in what load_view reads, and one renderer (geometry, lights, acceleration
// structure) serves them all.
bool animates_view_only(const Scene& s);
// Whether the glTF animation moves the world (scene_pose.h) while every [[animate]] key lies
// under camera, image or render: then a frame is the loaded scene posed again (pose_scene) with
// its view read by load_view, the same scene a load of that frame gives.
bool animates_view_and_pose(const Scene& s);

// The frame `frame` of `file` for such an animation: only [image], [render] and [camera] are read
// (the other tables are neither loaded nor validated again), a model camera (`gltf_camera`) comes
// from `loaded`, a scene loaded from the same file and overrides. The result has no geometry,
// materials, lights or environment: its camera and settings go with `loaded`'s.
Scene load_view(const std::filesystem::path& file, const std::vector<std::string>& overrides,
                double frame, const Scene& loaded);
// Checks frame `frame` of `file` as load_scene would read it, without loading models or images
// (their files must exist) and without keeping the result: every key's value, the camera built.
// `loaded` is a scene loaded from the same file and overrides (its model cameras serve
// `gltf_camera`; when it animates only the view, only the view is read). Throws SceneError, an
// [[animate]] value's at its entry with the frame (`render --frames` checks every frame so before
// rendering the first).
void check_scene_frame(const std::filesystem::path& file, const std::vector<std::string>& overrides,
                       double frame, const Scene& loaded);

// Same, from TOML text (the editor: a document whose edits change only the view).
Scene load_view_from_string(const std::string& text, const std::filesystem::path& name,
                            const std::vector<std::string>& overrides, double frame,
                            const Scene& loaded);

// A scene's view (image, render, camera, animate) parsed once and built many times with different
// overrides: the solver's cameras (src/solve). `build` is load_view_from_string of the text
// without the tables `without` (dotted keys, e.g. "camera.coin") and without the scene's texts
// (effective_toml, camera_toml) or its read files (inputs). Throws SceneError as it does.
class ViewTemplate {
 public:
  ViewTemplate(const std::string& text, const std::filesystem::path& name,
               const std::vector<std::string>& without = {});
  ~ViewTemplate();
  ViewTemplate(const ViewTemplate&) = delete;
  ViewTemplate& operator=(const ViewTemplate&) = delete;
  Scene build(const std::vector<std::string>& overrides, double frame, const Scene& loaded) const;

 private:
  struct Parsed;
  std::unique_ptr<Parsed> parsed_;
  std::filesystem::path name_;
};

}  // namespace anamorph
