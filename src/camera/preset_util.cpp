#include "camera/preset_util.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "math/fast_trig.h"

namespace anamorph {

Vec2 window_half_extent(double e, std::string_view axis, double a) {
  if (axis == "vertical") return {e * a, e};
  if (axis == "diagonal") {
    const double d = std::sqrt(1 + a * a);
    return {e * a / d, e / d};
  }
  return {e, e / a};
}

bool radial_direction(double a, double b, double theta, double dtheta, RadialDirection* out) {
  double st, ct;
  sincos_poly(theta, &st, &ct);
  bool axis;
  *out = radial_lane(a, b, st, ct, dtheta, &axis);
  return !axis || std::abs(theta) <= 1e-9;
}

double polar_angle(const Vec3& v, Vec2* azimuth) {
  const double rho = std::sqrt(v.x * v.x + v.y * v.y);
  *azimuth = rho > 0 ? Vec2{v.x / rho, v.y / rho} : Vec2{0, 0};
  return std::atan2(rho, -v.z);
}

namespace {

class SegmentOrg final : public OrgFunctionLoop<SegmentOrg> {
 public:
  SegmentOrg(Vec3 c, Vec3 e, bool along_v) : c_(c), e_(e), along_v_(along_v) {}
  bool eval(Vec2 uv, SurfaceSample* out) const override {
    clear(out);
    const double t = along_v_ ? uv.y : uv.x;
    out->p = c_ + e_ * (t - 0.5);
    (along_v_ ? out->dpdv : out->dpdu) = e_;
    return true;
  }

 private:
  Vec3 c_, e_;
  bool along_v_;
};

}  // namespace

std::unique_ptr<OrgFunction> make_segment_org(Vec3 center, Vec3 edge, bool along_v) {
  return std::make_unique<SegmentOrg>(center, edge, along_v);
}

AngleRange read_angle_range(const ParamValues& v, std::string_view key, double limit_deg) {
  const Vec2 r = v.vec2(key);
  const std::string k(key);
  if (!(r.x < r.y))
    throw ParamError(
        k, fmt::format("{} must be [low, high] with low < high (got [{:g}, {:g}])", k, r.x, r.y));
  if (r.y - r.x > 2 * limit_deg + 1e-9)
    throw ParamError(k, fmt::format("{} may span at most {:g} degrees", k, 2 * limit_deg));
  return {radians(r.x), radians(r.y)};
}

int longitude_to_u(double lon, const AngleRange& r, double out[3]) {
  int n = 0;
  for (double shift : {0.0, -2 * kPi, 2 * kPi}) {
    double u = (lon + shift - r.lo) / r.span();
    if (!(u >= -1e-9 && u <= 1 + 1e-9)) continue;
    u = std::clamp(u, 0.0, 1.0);
    bool dup = false;
    for (int i = 0; i < n; ++i) dup |= std::abs(out[i] - u) < 1e-12;
    if (!dup) out[n++] = u;
  }
  return n;
}

bool clamp_to_image(Vec2* uv) {
  constexpr double tol = 1e-9;
  if (!(uv->x >= -tol && uv->x <= 1 + tol && uv->y >= -tol && uv->y <= 1 + tol)) return false;
  uv->x = std::clamp(uv->x, 0.0, 1.0);
  uv->y = std::clamp(uv->y, 0.0, 1.0);
  return true;
}

}  // namespace anamorph
