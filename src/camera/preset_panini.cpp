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
#include "math/simd.h"

namespace anamorph {

namespace {

const std::string_view kFovAxes[] = {"horizontal", "vertical"};

const ParamSpec kParams[] = {
    ANAMORPH_LOOK_AT_PARAMS,
    {.name = "fov",
     .type = ParamType::Number,
     .default_value = "120",
     .doc = "Field of view in degrees along fov_axis. Horizontal: below 2 acos(-min(d, 1/d)).",
     .min = 0,
     .max = 360,
     .min_exclusive = true,
     .max_exclusive = true,
     .unit = "degrees"},
    {"fov_axis", ParamType::String, "\"horizontal\"",
     "Which image extent `fov` spans (vertical: through the image center).", -kInf, kInf, kFovAxes},
    {"compression", ParamType::Number, "1",
     "Panini's d: 0 = perspective, 1 = the standard Panini, larger = more compression.", 0, kInf},
};

struct PaniniGeometry {
  Vec2 half;
  double d;
};

// The directions of a batch: cos(lon) of the image abscissa x is the larger root of
// (k + 1) c^2 + 2 k d c + k d^2 - 1 = 0; no ray where d + cos(lon) <= 0.
[[gnu::always_inline]] inline void panini_kernel(const PaniniGeometry& geo,
                                                 const double* __restrict u,
                                                 const double* __restrict v, int n,
                                                 DirBatch* __restrict out) {
  const PaniniGeometry g = geo;
  const double d = g.d, d1 = d + 1;
  alignas(64) double dc[kCameraBatch];
  for (int i = 0; i < n; ++i) {
    const double x = (2 * u[i] - 1) * g.half.x, y = (1 - 2 * v[i]) * g.half.y;
    const double k = x * x / (d1 * d1);
    const double disc = k * k * d * d - (k + 1) * (k * d * d - 1);
    const double c = (-k * d + std::sqrt(disc < 0.0 ? 0.0 : disc)) / (k + 1);
    const double sin_lon = x * (d + c) / d1;
    // z = (d+1) c / (d+c); dz/dx = -d sin(lon) / (d cos(lon) + 1).
    dc[i] = d + c;
    out->d[0][i] = x, out->d[1][i] = y, out->d[2][i] = -d1 * c / (d + c);
    out->du[0][i] = 1 * (2 * g.half.x), out->du[1][i] = 0 * (2 * g.half.x);
    out->du[2][i] = d * sin_lon / (d * c + 1) * (2 * g.half.x);
    out->dv[0][i] = 0 * (-2 * g.half.y), out->dv[1][i] = 1 * (-2 * g.half.y);
    out->dv[2][i] = 0 * (-2 * g.half.y);
  }
  for (int i = 0; i < n; ++i) out->ok[i] = dc[i] > 0;
}

ANAMORPH_KERNEL_BODY void panini_dirs_body(const PaniniGeometry& g, const double* u,
                                           const double* v, int n, DirBatch* out) {
  with_trip_count<kCameraBatch>(
      n, [&](auto m) __attribute__((always_inline)) { panini_kernel(g, u, v, m, out); });
}
constexpr simd::Kernel<panini_dirs_body> panini_dirs;

class PaniniDir final : public DirFunction {
 public:
  PaniniDir(Vec2 half, double d) : g_{half, d} {}
  bool eval(Vec2 uv, const SurfaceSample& org, DirSample* out) const override {
    return eval_as_batch_of_one(*this, uv, org, out);
  }
  void eval_batch(const double* u, const double* v, int n, const SurfaceBatch&,
                  DirBatch* out) const override {
    panini_dirs(g_, u, v, n, out);
  }

 private:
  PaniniGeometry g_;
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
