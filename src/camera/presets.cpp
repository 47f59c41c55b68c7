// The one list of presets (adding a preset = one line in camera_presets), and what is derived
// from their parameter tables.
#include "camera/presets.h"

#include <sstream>
#include <vector>

#include "camera/functions.h"
#include "camera/preset_list.h"
#include "math/dual.h"
#include "params/param_docs.h"

namespace anamorph {

Transform rig_from_look_at(const ParamValues& v) {
  const Vec3 from = v.vec3("look_from"), at = v.vec3("look_at"), up = v.vec3("up");
  if (!(length(at - from) > 0)) throw ParamError("look_at", "look_at must differ from look_from");
  if (!(length(cross(at - from, up)) > 1e-12 * length(at - from) * length(up)))
    throw ParamError("up",
                     "up must not be parallel to the viewing direction (look_at - look_from)");
  return Transform::look_at(from, at, up);
}

std::function<bool(std::string_view, int, Mat4*)> look_at_rig_derivative(const ParamValues& v) {
  const Vec3 from = v.vec3("look_from"), at = v.vec3("look_at"), up = v.vec3("up");
  const Mat4 inv = rig_from_look_at(v).inverse_matrix();
  return [=](std::string_view key, int c, Mat4* g) {
    const int which = key == "look_from" ? 0 : key == "look_at" ? 1 : key == "up" ? 2 : -1;
    if (which < 0 || c < 0 || c > 2) return false;
    DVec3 f = dual(from), a = dual(at), u = dual(up);
    (which == 0 ? f : which == 1 ? a : u)[c].d = 1;
    // As Transform::look_at: columns right, true up, -forward and the eye.
    const DVec3 fw = dual_normalize(a - f), r = dual_normalize(cross(fw, u)), tu = cross(r, fw);
    Mat4 dm;
    for (int k = 0; k < 3; ++k) {
      dm.m[size_t(k)][0] = r[k].d, dm.m[size_t(k)][1] = tu[k].d;
      dm.m[size_t(k)][2] = -fw[k].d, dm.m[size_t(k)][3] = f[k].d;
    }
    *g = inv * dm;
    return true;
  };
}

std::span<const PresetInfo> camera_presets() {
  static const std::vector<PresetInfo> list = {kPerspectivePreset,
                                               kOrthographicPreset,
                                               kFisheyePreset,
                                               kMirrorBallPreset,
                                               kDomePreset,
                                               kOpenCvPinholePreset,
                                               kOpenCvFisheyePreset,
                                               kEquirectangularPreset,
                                               kCylindricalPreset,
                                               kMercatorPreset,
                                               kLambertEqualAreaPreset,
                                               kStereographicPreset,
                                               kPaniniPreset,
                                               kCubemapPreset,
                                               kOdsPreset,
                                               kLightFieldPreset,
                                               kIntegralPreset,
                                               kPushbroomPreset,
                                               kCrossedSlitsPreset};
  return list;
}

const PresetInfo* find_preset(std::string_view name) {
  for (const auto& p : camera_presets())
    if (p.name == name) return &p;
  return nullptr;
}

VirtualCameraParts make_preset(std::string_view name, std::string_view toml_text, ImageInfo img) {
  const PresetInfo* info = find_preset(name);
  if (!info) {
    std::ostringstream msg;
    msg << "unknown preset '" << name << "' (valid:";
    for (const auto& p : camera_presets()) msg << ' ' << p.name;
    msg << ')';
    throw ParamError("preset", msg.str());
  }
  return info->create(params_from_toml(info->params, toml_text), img);
}

std::string preset_params_markdown(const PresetInfo& p) { return params_markdown_table(p.params); }

}  // namespace anamorph
