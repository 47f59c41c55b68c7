// panini: the Panini (vedutismo) projection of Sharpless, Postle and German (2010) with
// compression d. A direction (lon, lat) lands at
//   x = S sin(lon),  y = S tan(lat),  S = (d + 1) / (d + cos(lon)),
// so verticals stay vertical and the horizon is compressed; d = 0 is the perspective camera.
// org = point, dir = PaniniDir: dir(x, y) = (x, y, -S cos(lon)) where cos(lon) solves
// (k + 1) c^2 + 2 k d c + k d^2 - 1 = 0 with k = x^2 / (d + 1)^2 (the larger root).
#include <cmath>

#include <fmt/format.h>

#include "camera/org_basic.h"
#include "camera/preset_list.h"
#include "camera/preset_util.h"

namespace anamorph {

namespace {

const std::string_view kFovAxes[] = {"horizontal", "vertical"};

const ParamSpec kParams[] = {
    ANAMORPH_LOOK_AT_PARAMS,
    {"fov",
     ParamType::Number,
     "120",
     "Field of view in degrees along fov_axis. Horizontal: below 2 acos(-min(d, 1/d)).",
     0,
     360,
     {},
     true,
     true},
    {"fov_axis", ParamType::String, "\"horizontal\"",
     "Which image extent `fov` spans (vertical: through the image center).", -kInf, kInf, kFovAxes},
    {"compression", ParamType::Number, "1",
     "Panini's d: 0 = perspective, 1 = the standard Panini, larger = more compression.", 0, kInf},
};

// cos(lon) of image abscissa x.
double panini_cos_lon(double x, double d) {
  const double k = x * x / ((d + 1) * (d + 1));
  const double disc = k * k * d * d - (k + 1) * (k * d * d - 1);
  return (-k * d + std::sqrt(std::max(disc, 0.0))) / (k + 1);
}

class PaniniDir final : public DirFunctionLoop<PaniniDir> {
 public:
  PaniniDir(Vec2 half, double d) : half_(half), d_(d) {}
  bool eval(Vec2 uv, const SurfaceSample&, DirSample* out) const override {
    const double x = (2 * uv.x - 1) * half_.x, y = (1 - 2 * uv.y) * half_.y;
    const double c = panini_cos_lon(x, d_);
    if (!(d_ + c > 0)) return false;
    const double sin_lon = x * (d_ + c) / (d_ + 1);
    // z = (d+1) c / (d+c); dz/dx = -d sin(lon) / (d cos(lon) + 1).
    out->d = {x, y, -(d_ + 1) * c / (d_ + c)};
    out->dd_du = Vec3{1, 0, d_ * sin_lon / (d_ * c + 1)} * (2 * half_.x);
    out->dd_dv = Vec3{0, 1, 0} * (-2 * half_.y);
    return true;
  }

 private:
  Vec2 half_;
  double d_;
};

VirtualCameraParts create(const ParamValues& v, const ImageInfo& img) {
  check_params(kParams, v);
  const double d = v.number("compression");
  const double half_fov = radians(v.number("fov")) / 2;
  // x(lon) increases while d + cos(lon) > 0 and d cos(lon) + 1 > 0.
  const double lon_max = std::acos(-std::min(d, d > 0 ? 1 / d : 1.0));
  Vec2 half;
  if (v.string("fov_axis") == "horizontal") {
    if (!(half_fov < lon_max))
      throw ParamError("fov", fmt::format("with compression {:g} the horizontal fov must be "
                                          "below {:.6g} degrees",
                                          d, degrees(2 * lon_max)));
    half.x = (d + 1) * std::sin(half_fov) / (d + std::cos(half_fov));
    half.y = half.x / img.aspect();
  } else {
    if (!(half_fov < kPi / 2)) throw ParamError("fov", "a vertical fov must be below 180 degrees");
    half.y = std::tan(half_fov);
    half.x = half.y * img.aspect();
    // The widest abscissa the projection reaches (infinite when d <= 1).
    const double x_max = d > 1 ? (d + 1) * std::sin(lon_max) / (d + std::cos(lon_max)) : kInf;
    if (!(half.x < x_max))
      throw ParamError("fov",
                       "this vertical fov makes the image wider than the Panini "
                       "projection with this compression reaches");
  }
  VirtualCameraParts p;
  p.org = make_point_org({});
  p.dir = std::make_unique<PaniniDir>(half, d);
  p.world_from_camera = rig_from_look_at(v);
  p.description = "panini (org point + dir panini)";
  p.inverse = make_inverse([half, d, lon_max](const Vec3& q) -> std::vector<Vec2> {
    const double rho = std::sqrt(q.x * q.x + q.z * q.z);
    if (!(rho > 0)) return {};
    const double lon = std::atan2(q.x, -q.z);
    if (!(std::abs(lon) < lon_max)) return {};
    const double s = (d + 1) / (d + std::cos(lon));
    Vec2 uv{0.5 + s * std::sin(lon) / (2 * half.x), 0.5 - s * (q.y / rho) / (2 * half.y)};
    if (!clamp_to_image(&uv)) return {};
    return {uv};
  });
  return p;
}

}  // namespace

const PresetInfo kPaniniPreset{
    "panini",
    "Panini projection (compression d): wide views with straight verticals and radial lines. "
    "org = point, dir = panini.",
    kParams, create};

}  // namespace anamorph
