// `render scene.glb`: the defaults of a glTF file read as a scene (gltf_scene.h).
#include "scene/gltf_scene.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>
#include <string>

#include "scene/world_extent.h"

namespace anamorph {

namespace fs = std::filesystem;

namespace {

// The default perspective preset's field of view (horizontal), which the framing view assumes.
constexpr double kFramingFovDegrees = 60;
// Where the framing view looks from, relative to the scene's centre (normalized): front-right,
// above.
constexpr Vec3 kFramingDirection{1, 0.75, 1};
// The image's width / height when the file's camera does not say (the [image] defaults').
constexpr double kDefaultAspect = 4.0 / 3.0;

// The world box of what `s` places (rest pose).
Bounds3 world_bounds(const Scene& s) {
  Bounds3 box;
  for (const Instance& inst : s.instances) {
    const Bounds3 b = prototype_bounds(s.prototypes[inst.prototype]);
    if (b.empty()) continue;
    for (int k = 0; k < 8; ++k)
      box.extend(inst.world_from_object.point(
          {k & 1 ? b.hi.x : b.lo.x, k & 2 ? b.hi.y : b.lo.y, k & 4 ? b.hi.z : b.lo.z}));
  }
  return box;
}

toml::array vec3(const Vec3& v) { return toml::array{v.x, v.y, v.z}; }

}  // namespace

bool is_gltf_scene_file(const fs::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return ext == ".gltf" || ext == ".glb";
}

toml::table gltf_scene_table(const fs::path& file) {
  toml::table object{{"type", "mesh"}, {"file", fs::absolute(file).string()}};
  return toml::table{
      {"render", toml::table{{"integrator", "path"}, {"spp", 64}, {"max_depth", 9}}},
      {"environment", toml::table{{"color", 0.05}}},
      {"object", toml::array{std::move(object)}},
  };
}

void complete_gltf_view(toml::table& root, const Scene& geometry,
                        const std::vector<ModelCamera>& cameras, RenderSettings& render) {
  if (!root.contains("camera")) root.insert("camera", toml::table{});
  toml::table* cam = root.get("camera")->as_table();
  if (!cam) return;  // (not a table: the camera reader says so)
  const bool placed = cam->contains("gltf_camera") || cam->contains("look_from") ||
                      cam->contains("look_at") || cam->contains("org") || cam->contains("dir");
  if (!placed && !cameras.empty()) cam->insert("gltf_camera", 0);
  // The image height follows the width at the camera's aspect ratio (4:3 without one).
  const toml::table* image = root.get("image") ? root.get("image")->as_table() : nullptr;
  const std::optional<int64_t> index = (*cam)["gltf_camera"].value<int64_t>();
  double aspect = kDefaultAspect;
  if (index && *index >= 0 && size_t(*index) < cameras.size()) {
    const ModelCamera& mc = cameras[size_t(*index)];
    if (mc.perspective && mc.aspect > 0 && std::isfinite(mc.aspect)) aspect = mc.aspect;
  }
  if (!(image && image->contains("height")))
    render.height = std::clamp(int(std::lround(render.width / aspect)), 1, 65536);
  if (index) return;
  if (placed) return;
  const Bounds3 box = world_bounds(geometry);
  Vec3 center{0, 0, 0};
  double radius = 1;
  if (!box.empty()) {
    center = (box.lo + box.hi) * 0.5;
    radius = std::max(0.5 * length(box.hi - box.lo), 1e-6);
  }
  const double image_aspect = double(render.width) / render.height;
  const double half_h = kFramingFovDegrees * kPi / 360;
  const double half = std::min(half_h, std::atan(std::tan(half_h) / image_aspect));
  const Vec3 from = center + normalize(kFramingDirection) * (radius / std::sin(half));
  cam->insert("look_from", vec3(from));
  cam->insert("look_at", vec3(center));
}

}  // namespace anamorph
