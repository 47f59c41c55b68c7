#include "scene/camera_reader.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "camera/coins.h"
#include "camera/dir_basic.h"
#include "camera/org_basic.h"
#include "camera/virtual_camera.h"
#include "scene/camera_goals.h"
#include "scene/scene_schema.h"

namespace anamorph {

namespace {

const std::string_view kRolling[] = {"none",          "top_to_bottom", "bottom_to_top",
                                     "left_to_right", "right_to_left", "angle"};

template <class Info>
auto create_checked(const TableReader& r, const Info& info, const ParamValues& v) {
  try {
    return info.create(v);
  } catch (const ParamError& e) {
    r.fail(e.key, e.message());
  }
}

constexpr std::string_view kTypeKey[] = {"type"};

// camera.org or camera.dir: a table { type = "...", ... } with the type's declared keys.
const toml::table& function_table(const TableReader& cam, std::string_view key) {
  const toml::node* n = cam.node(key);
  if (!n || !n->is_table()) cam.fail(key, "expected a table { type = \"...\", ... }");
  return *n->as_table();
}

std::unique_ptr<OrgFunction> read_org(const TableReader& cam) {
  const TableReader r(function_table(cam, "org"), cam.full_key("org"));
  const OrgFunctionInfo& info = *find_org_function(r.selector(org_type_spec()));
  return create_checked(r, info, r.params({info.params}, kTypeKey));
}

std::unique_ptr<DirFunction> read_dir(const TableReader& cam) {
  const TableReader r(function_table(cam, "dir"), cam.full_key("dir"));
  const DirFunctionInfo& info = *find_dir_function(r.selector(dir_type_spec()));
  return create_checked(r, info, r.params({info.params}, kTypeKey));
}

// [[camera.coin]] entries (centers of interest, docs/coins.md); errors name camera.coin[i].key.
std::vector<Coin> read_coins(const TableReader& cam) {
  std::vector<Coin> coins;
  const toml::node* n = cam.node("coin");
  if (!n) return coins;
  const toml::array* a = n->as_array();
  if (!a || !a->is_array_of_tables())
    cam.fail("coin", "expected an array of tables ([[camera.coin]] entries)");
  for (size_t i = 0; i < a->size(); ++i) {
    const TableReader r(*a->get(i)->as_table(), cam.full_key(fmt::format("coin[{}]", i)));
    const ParamValues v = r.params({coin_params()});
    try {
      coins.push_back(coin_from_params(v));
    } catch (const ParamError& e) {
      r.fail(e.key, e.message());
    }
  }
  return coins;
}

VirtualCameraParts from_model_camera(const ModelCamera& m, ImageInfo img) {
  VirtualCameraParts p;
  if (m.perspective) {
    // yfov kept, the width from the image's own aspect: an image of another shape than the file's
    // aspectRatio (which sets the default height, gltf_scene.cpp) shows more or less to the
    // sides, never a stretched view.
    const double h = 2 * std::tan(m.yfov * 0.5), w = h * img.aspect();
    p.org = make_point_org({0, 0, 0});
    p.dir = make_surface_dir(make_plane_org({0, 0, -1}, {w, 0, 0}, {0, -h, 0}), {0, 0, 0});
    p.description = fmt::format("glTF perspective camera '{}' (yfov {:.4g} rad)", m.name, m.yfov);
  } else {
    p.org = make_plane_org({0, 0, 0}, {2 * m.xmag, 0, 0}, {0, -2 * m.ymag, 0});
    p.dir = make_constant_dir({0, 0, -1});
    p.description = fmt::format("glTF orthographic camera '{}'", m.name);
  }
  p.world_from_camera = m.world_from_camera;
  return p;
}

}  // namespace

namespace {

// The shutter keys: [open, close] in frames relative to the frame rendered (default:
// instantaneous) and the rolling shutter's readout direction.
void read_shutter(const TableReader& r, const ParamValues& v, CameraSpec* spec) {
  const Vec2 oc = v.vec2("shutter");
  if (oc.y < oc.x) r.fail("shutter", "expected finite [open, close] with close >= open");
  spec->shutter_open = oc.x;
  spec->shutter_close = oc.y;
  Shutter* shutter = &spec->parts.shutter;
  const std::string& rolling = v.string("rolling_shutter");
  shutter->rolling = rolling != "none";
  const double angles[] = {0, 90, 270, 0, 180};
  const size_t i =
      size_t(std::find(std::begin(kRolling), std::end(kRolling), rolling) - std::begin(kRolling));
  if (rolling != "angle" && v.has("rolling_shutter_angle"))
    r.fail("rolling_shutter_angle", "only used with rolling_shutter = \"angle\"");
  shutter->rolling_angle =
      rolling == "angle" ? (v.has("rolling_shutter_angle") ? v.number("rolling_shutter_angle") : 90)
                         : (i < 5 ? angles[i] : 90);
}

// A preset camera; keys of the file's preset that a preset chosen with --set does not have are
// dropped with a warning (`preset_overridden`).
VirtualCameraParts read_preset(const TableReader& r, ImageInfo img, bool preset_overridden,
                               std::vector<std::string>* warnings, ParamValues* common) {
  const std::string name = r.selector(camera_preset_spec());
  const PresetInfo& info = *find_preset(name);
  std::vector<std::string> dropped;
  if (preset_overridden)
    for (const auto& [k, v] : r.table()) {
      const std::string_view key = k.str();
      if (key == "preset" || key == "coin" || is_goal_key(key) ||
          find_param({info.params, camera_common_params()}, key))
        continue;
      dropped.emplace_back(key);
      if (warnings)
        warnings->push_back(
            fmt::format("camera.{}: ignored, preset \"{}\" has no such key", key, name));
    }
  // Two walks over the one table: the preset's keys (for its factory, which takes only its
  // own) and the common ones, each accepting the other's.
  std::vector<std::string_view> also{"preset", "coin", "constraint", "free", "solve"};
  also.insert(also.end(), dropped.begin(), dropped.end());
  std::vector<std::string_view> also_common = also, also_preset = also;
  for (const ParamSpec& s : info.params) also_common.push_back(s.name);
  for (const ParamSpec& s : camera_common_params()) also_preset.push_back(s.name);
  *common = r.params({camera_common_params()}, also_common);
  const ParamValues v = r.params({info.params}, also_preset);
  try {
    return info.create(v, img);
  } catch (const ParamError& e) {
    r.fail(e.key, e.message());
  }
}

}  // namespace

namespace {

// The model camera `gltf_camera` names.
const ModelCamera& named_model_camera(const TableReader& r,
                                      const std::vector<ModelCamera>& model_cameras) {
  const toml::node* n = r.node("gltf_camera");
  const std::optional<int64_t> idx = n->value<int64_t>();
  if (!idx || *idx < 0) r.fail("gltf_camera", "expected the index of a camera (0, 1, ...)");
  if (model_cameras.empty())
    r.fail("gltf_camera",
           "no loaded model contains a camera (Blender exports no camera for its panoramic "
           "cameras; docs/gltf.md)");
  if (size_t(*idx) >= model_cameras.size())
    r.fail("gltf_camera", fmt::format("there are {} cameras in the loaded models (0..{})",
                                      model_cameras.size(), model_cameras.size() - 1));
  return model_cameras[size_t(*idx)];
}

// gltf_camera without a preset or functions takes the glTF camera's own projection: a preset's
// key then has nothing to apply to, which the message says instead of "unknown key".
void refuse_preset_keys(const TableReader& r) {
  for (const auto& [k, v] : r.table()) {
    const std::string_view key = k.str();
    if (key == "coin" || is_goal_key(key) || find_param({camera_common_params()}, key)) continue;
    for (const PresetInfo& p : camera_presets())
      if (find_param({p.params}, key))
        r.fail(key, fmt::format("a key of camera presets (e.g. \"{}\"): gltf_camera without a "
                                "preset uses the glTF camera's own projection; name a preset "
                                "(preset = \"{}\") to use {} with the glTF camera's pose",
                                p.name, p.name, key));
  }
}

}  // namespace

CameraSpec read_camera(const TableReader& r, ImageInfo img,
                       const std::vector<ModelCamera>& model_cameras, bool preset_overridden,
                       std::vector<std::string>* warnings) {
  CameraSpec spec;
  VirtualCameraParts& parts = spec.parts;
  ParamValues v;
  const bool composed = r.has("org") || r.has("dir");
  const bool gltf_camera = r.has("gltf_camera");
  // A preset's own look_from / look_at / up would place it a second time.
  if (gltf_camera && r.has("preset"))
    for (const char* key : {"look_from", "look_at", "up"})
      if (r.has(key))
        r.fail(key,
               "conflicts with gltf_camera: the glTF camera node places the camera (move the "
               "whole rig with `transform`)");
  if (gltf_camera && !composed && !r.has("preset")) {
    refuse_preset_keys(r);
    static constexpr std::string_view kAlso[] = {"coin", "constraint", "free", "solve"};
    v = r.params({camera_common_params()}, kAlso);
    parts = from_model_camera(named_model_camera(r, model_cameras), img);
  } else if (composed) {
    if (r.has("preset")) r.fail("preset", "give either a preset or org/dir functions, not both");
    if (!r.has("org")) r.fail("org", "is required when dir is given");
    if (!r.has("dir")) r.fail("dir", "is required when org is given");
    static constexpr std::string_view kAlso[] = {"org",        "dir",  "coin",
                                                 "constraint", "free", "solve"};
    v = r.params({camera_common_params()}, kAlso);
    parts.org = read_org(r);
    parts.dir = read_dir(r);
    const auto type_of = [&](const char* k) {
      return std::string(*r.table().get(k)->as_table()->get("type")->value<std::string>());
    };
    parts.description = fmt::format("org {} + dir {}", type_of("org"), type_of("dir"));
    if (type_of("org") == "point" && type_of("dir") == "constant" && warnings)
      warnings->push_back(
          "camera: org = point with dir = constant gives every pixel the same ray (a uniform "
          "image)");
  } else {
    parts = read_preset(r, img, preset_overridden, warnings, &v);
  }
  if (gltf_camera) {
    const ModelCamera& mc = named_model_camera(r, model_cameras);
    parts.world_from_camera = mc.world_from_camera;
    parts.derivatives.rig = nullptr;  // (the preset's look_at no longer places it)
    if (composed || r.has("preset"))
      parts.description += fmt::format(" at glTF camera '{}'", mc.name);
  }
  DepthOfField& dof = spec.dof;
  dof.aperture_radius = v.number("aperture_radius");
  dof.focus_distance = v.number("focus_distance");
  if (dof.aperture_radius > 0 && !(dof.focus_distance > 0))
    r.fail("focus_distance", "must be > 0 when aperture_radius > 0");
  // (Always multiplied, as before: an identity product keeps the bits of every image.)
  parts.world_from_camera =
      (v.has("transform") ? v.transform("transform") : Transform()) * parts.world_from_camera;
  parts.coins = read_coins(r);
  read_camera_goals(
      r);  // (checked here, so that every command refuses a bad goal; solve/ uses them)
  read_shutter(r, v, &spec);
  return spec;
}

}  // namespace anamorph
