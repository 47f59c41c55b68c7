#include "scene/camera_reader.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "camera/coins.h"
#include "camera/dir_basic.h"
#include "camera/org_basic.h"
#include "camera/virtual_camera.h"

namespace anamorph {

namespace {

// Keys every camera form accepts.
const char* const kCommonKeys[] = {"transform", "aperture_radius", "focus_distance",       "coin",
                                   "shutter",   "rolling_shutter", "rolling_shutter_angle"};
const std::string_view kRolling[] = {"none",          "top_to_bottom", "bottom_to_top",
                                     "left_to_right", "right_to_left", "angle"};

template <class Info>
auto create_checked(TableReader& r, const Info& info, const ParamValues& v) {
  try {
    return info.create(v);
  } catch (const ParamError& e) {
    r.fail(e.key, e.what());
  }
}

std::unique_ptr<OrgFunction> read_org(TableReader& cam) {
  const toml::node* n = cam.node("org");
  if (!n || !n->is_table()) cam.fail("org", "expected a table { type = \"...\", ... }");
  TableReader r(*n->as_table(), cam.full_key("org"));
  std::vector<std::string_view> names;
  for (const auto& f : org_functions()) names.push_back(f.name);
  const std::string type = r.string("type", "", names);
  if (type.empty()) r.fail("type", "is required");
  const OrgFunctionInfo& info = *find_org_function(type);
  const ParamValues v = r.params(info.params);
  r.finish();
  return create_checked(r, info, v);
}

std::unique_ptr<DirFunction> read_dir(TableReader& cam) {
  const toml::node* n = cam.node("dir");
  if (!n || !n->is_table()) cam.fail("dir", "expected a table { type = \"...\", ... }");
  TableReader r(*n->as_table(), cam.full_key("dir"));
  std::vector<std::string_view> names;
  for (const auto& f : dir_functions()) names.push_back(f.name);
  const std::string type = r.string("type", "", names);
  if (type.empty()) r.fail("type", "is required");
  const DirFunctionInfo& info = *find_dir_function(type);
  const ParamValues v = r.params(info.params);
  r.finish();
  return create_checked(r, info, v);
}

// [[camera.coin]] entries (centers of interest, docs/coins.md); errors name camera.coin[i].key.
std::vector<Coin> read_coins(TableReader& cam) {
  std::vector<Coin> coins;
  const toml::node* n = cam.node("coin");
  if (!n) return coins;
  const toml::array* a = n->as_array();
  if (!a || !a->is_array_of_tables())
    cam.fail("coin", "expected an array of tables ([[camera.coin]] entries)");
  for (size_t i = 0; i < a->size(); ++i) {
    TableReader r(*a->get(i)->as_table(), cam.full_key(fmt::format("coin[{}]", i)));
    const ParamValues v = r.params(coin_params());
    r.finish();
    try {
      coins.push_back(coin_from_params(v));
    } catch (const ParamError& e) {
      r.fail(e.key, e.what());
    }
  }
  return coins;
}

VirtualCameraParts from_model_camera(const ModelCamera& m, ImageInfo img) {
  VirtualCameraParts p;
  const double a = m.aspect > 0 ? m.aspect : img.aspect();
  if (m.perspective) {
    const double h = 2 * std::tan(m.yfov * 0.5), w = h * a;
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

std::unique_ptr<Camera> read_camera(TableReader& r, ImageInfo img,
                                    const std::vector<ModelCamera>& model_cameras,
                                    bool preset_overridden, std::vector<std::string>* warnings,
                                    ShutterSpec* shutter) {
  VirtualCameraParts parts;
  const bool composed = r.has("org") || r.has("dir");
  if (r.has("gltf_camera")) {
    const auto idx = r.integer("gltf_camera", 0, 0, 1 << 20);
    if (model_cameras.empty()) r.fail("gltf_camera", "no loaded model contains a camera");
    if (size_t(idx) >= model_cameras.size())
      r.fail("gltf_camera", fmt::format("there are {} cameras in the loaded models (0..{})",
                                        model_cameras.size(), model_cameras.size() - 1));
    if (composed || r.has("preset"))
      r.fail("gltf_camera", "cannot be combined with preset or org/dir");
    parts = from_model_camera(model_cameras[size_t(idx)], img);
  } else if (composed) {
    if (r.has("preset")) r.fail("preset", "give either a preset or org/dir functions, not both");
    if (!r.has("org")) r.fail("org", "is required when dir is given");
    if (!r.has("dir")) r.fail("dir", "is required when org is given");
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
    std::vector<std::string_view> names;
    for (const auto& p : camera_presets()) names.push_back(p.name);
    const std::string name = r.string("preset", "perspective", names);
    const PresetInfo& info = *find_preset(name);
    if (preset_overridden) {
      // Keys that belonged to the file's preset but not to the one chosen on the command line.
      for (const auto& [k, v] : r.table()) {
        const std::string_view key = k.str();
        bool known = key == "preset";
        for (const auto& s : info.params) known |= s.name == key;
        for (const char* c : kCommonKeys) known |= key == c;
        if (!known) {
          r.allow(key);
          if (warnings)
            warnings->push_back(
                fmt::format("camera.{}: ignored, preset \"{}\" has no such key", key, name));
        }
      }
    }
    const ParamValues v = r.params(info.params);
    try {
      parts = info.create(v, img);
    } catch (const ParamError& e) {
      r.fail(e.key, e.what());
    }
  }
  DepthOfField dof;
  dof.aperture_radius = r.number("aperture_radius", 0, 0);
  dof.focus_distance = r.number("focus_distance", 1, 0);
  if (dof.aperture_radius > 0 && !(dof.focus_distance > 0))
    r.fail("focus_distance", "must be > 0 when aperture_radius > 0");
  parts.world_from_camera = r.transform("transform") * parts.world_from_camera;
  parts.coins = read_coins(r);
  ShutterSpec local;
  if (!shutter) shutter = &local;
  {
    // shutter = [open, close] in frames relative to the frame rendered (default: instantaneous).
    shutter->open = shutter->close = 0;
    if (const toml::node* n = r.node("shutter")) {
      const toml::array* a = n->as_array();
      if (!a || a->size() != 2 || !a->get(0)->value<double>() || !a->get(1)->value<double>())
        r.fail("shutter", "expected [open, close] in frames, e.g. [0, 0.5]");
      shutter->open = *a->get(0)->value<double>();
      shutter->close = *a->get(1)->value<double>();
      if (!std::isfinite(shutter->open) || !std::isfinite(shutter->close) ||
          shutter->close < shutter->open)
        r.fail("shutter", "expected finite [open, close] with close >= open");
    }
    const std::string rolling = r.string("rolling_shutter", "none", kRolling);
    shutter->shutter.rolling = rolling != "none";
    const double angles[] = {0, 90, 270, 0, 180};
    const size_t i =
        size_t(std::find(std::begin(kRolling), std::end(kRolling), rolling) - std::begin(kRolling));
    shutter->shutter.rolling_angle =
        rolling == "angle" ? r.number("rolling_shutter_angle", 90) : (i < 5 ? angles[i] : 90);
    if (rolling != "angle" && r.has("rolling_shutter_angle"))
      r.fail("rolling_shutter_angle", "only used with rolling_shutter = \"angle\"");
  }
  r.finish();
  auto cam = std::make_unique<VirtualCamera>(std::move(parts), dof);
  if (warnings)
    for (const std::string& w : cam->coin_warnings()) warnings->push_back("camera." + w);
  return cam;
}

}  // namespace anamorph
