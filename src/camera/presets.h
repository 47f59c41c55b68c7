// Presets: named, documented compositions of origin and direction functions. A preset is never
// its own ray-generation code path; it only builds VirtualCameraParts.
#pragma once

#include <functional>
#include <span>
#include <string>
#include <string_view>

#include "camera/virtual_camera.h"
#include "params/params.h"

namespace anamorph {

struct ImageInfo {
  int width = 1;
  int height = 1;
  double aspect() const { return double(width) / double(height); }
};

struct PresetInfo {
  std::string_view name;
  std::string_view doc;
  std::span<const ParamSpec> params;
  VirtualCameraParts (*create)(const ParamValues&, const ImageInfo&);
};

std::span<const PresetInfo> camera_presets();
const PresetInfo* find_preset(std::string_view name);

// Builds a preset from TOML text holding some of its keys, the rest from the table's defaults,
// e.g. make_preset("fisheye", "fov = 200", {1024, 1024}). For tests and tools; scene files go
// through the scene parser. Throws ParamError (unknown preset or key, bad value).
VirtualCameraParts make_preset(std::string_view name, std::string_view toml_text, ImageInfo img);

// The Markdown parameter table of one preset (name | type | default | range | meaning), as
// docs/cameras.md shows it.
std::string preset_params_markdown(const PresetInfo& p);

// Shared by presets: the rig from look_from / look_at / up (forward f, right r = f x up,
// true up = r x f), mapping camera space (x right, y up, -z forward) to world.
Transform rig_from_look_at(const ParamValues& v);
// Its derivatives (PresetDerivatives::rig) with respect to look_from, look_at and up, exact (dual
// numbers through Transform::look_at).
std::function<bool(std::string_view key, int component, Mat4* g)> look_at_rig_derivative(
    const ParamValues& v);

// The common keys of look-at presets, to splice into their tables.
#define ANAMORPH_LOOK_AT_PARAMS                                                           \
  {"look_from", ParamType::Vec3, "[0, 0, 0]", "Eye position (world)."},                   \
      {"look_at", ParamType::Vec3, "[0, 0, -1]", "Point the camera looks at (world)."}, { \
    "up", ParamType::Vec3, "[0, 1, 0]", "Approximate up vector; need not be orthogonal."  \
  }

}  // namespace anamorph
