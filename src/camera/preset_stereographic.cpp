// stereographic: the conformal azimuthal projection as a full-frame camera ("little planet" at
// wide angles). org = point, dir = StereographicDir: for image-plane coordinates (x, y) with
// rho = |(x, y)| = tan(theta / 2),
//   dir = (2x, 2y, rho^2 - 1)   (length 1 + rho^2, never zero),
// the inverse of projecting the unit sphere from its back pole onto the plane tangent at -z.
#include <cmath>

#include "camera/org_basic.h"
#include "camera/preset_list.h"
#include "camera/preset_util.h"

namespace anamorph {

namespace {

const std::string_view kFovAxes[] = {"horizontal", "vertical", "diagonal"};

const ParamSpec kParams[] = {
    ANAMORPH_LOOK_AT_PARAMS,
    {.name = "fov",
     .type = ParamType::Number,
     .default_value = "180",
     .doc = "Field of view in degrees along fov_axis (below 360).",
     .min = 0,
     .max = 360,
     .min_exclusive = true,
     .max_exclusive = true,
     .unit = "degrees"},
    {"fov_axis", ParamType::String, "\"horizontal\"", "Which image extent `fov` spans.", -kInf,
     kInf, kFovAxes},
};

class StereographicDir final : public DirFunctionLoop<StereographicDir> {
 public:
  explicit StereographicDir(Vec2 half) : half_(half) {}
  bool eval(Vec2 uv, const SurfaceSample&, DirSample* out) const override {
    const double x = (2 * uv.x - 1) * half_.x, y = (1 - 2 * uv.y) * half_.y;
    out->d = {2 * x, 2 * y, x * x + y * y - 1};
    out->dd_du = Vec3{2, 0, 2 * x} * (2 * half_.x);
    out->dd_dv = Vec3{0, 2, 2 * y} * (-2 * half_.y);
    return true;
  }

 private:
  Vec2 half_;  // half extents of the window in plane units (tan(theta/2))
};

VirtualCameraParts create(const ParamValues& v, const ImageInfo& img) {
  check_params(kParams, v);
  const Vec2 half = window_half_extent(std::tan(radians(v.number("fov")) / 4), v.string("fov_axis"),
                                       img.aspect());
  VirtualCameraParts p;
  p.org = make_point_org({});
  p.dir = std::make_unique<StereographicDir>(half);
  p.world_from_camera = rig_from_look_at(v);
  p.description = "stereographic (org point + dir stereographic plane)";
  // (x, y) = (w.x, w.y) / (1 - w.z) for the unit direction w.
  p.inverse = make_inverse([half](const Vec3& q) -> std::vector<Vec2> {
    const double len = length(q);
    if (!(len > 0)) return {};
    const Vec3 w = q / len;
    const double den = 1 - w.z;
    if (!(den > 1e-300)) return {};
    Vec2 uv{0.5 + w.x / den / (2 * half.x), 0.5 - w.y / den / (2 * half.y)};
    if (!clamp_to_image(&uv)) return {};
    return {uv};
  });
  return p;
}

}  // namespace

const PresetInfo kStereographicPreset{
    "stereographic",
    "Stereographic (conformal azimuthal) projection filling the frame: image radius 2 "
    "tan(theta/2). "
    "org = point, dir = the sphere mapped from the tangent plane.",
    kParams, create};

}  // namespace anamorph
