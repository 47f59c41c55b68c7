// Helpers shared by the presets: image windows from a field of view, directions at a polar angle
// from the view axis (the fisheye family), degenerate origin sets (segments), longitude/latitude
// ranges and tiled layouts. Camera space throughout: x right, y up, looking along -z.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <string_view>

#include "camera/functions.h"
#include "camera/presets.h"
#include "params/params.h"

namespace anamorph {

// Half width and half height of an image window whose extent along `axis` ("horizontal",
// "vertical" or "diagonal") is 2 * half_extent, for square pixels at the given aspect (w / h).
Vec2 window_half_extent(double half_extent, std::string_view axis, double aspect);

// The direction at polar angle theta from the view axis (-z), with azimuth given by image-plane
// coordinates (a right, b up): d = (sin(theta) a / rho, sin(theta) b / rho, -cos(theta)) with
// rho = |(a, b)| and theta = theta(rho). Also its derivatives with respect to a and b, from
// dtheta = dtheta/drho. Returns false at rho = 0 when theta != 0 (no single direction there).
struct RadialDirection {
  Vec3 d, dd_da, dd_db;
};
bool radial_direction(double a, double b, double theta, double dtheta, RadialDirection* out);

// The same from sin and cos of theta, as straight-line code that batch kernels vectorize
// (selects for the axis, one division). *on_axis tells rho = 0, where theta must be 0.
[[gnu::always_inline]] inline RadialDirection radial_lane(double a, double b, double st, double ct,
                                                          double dtheta, bool* on_axis) {
  const double rho = std::sqrt(a * a + b * b);
  const bool axis = rho < 1e-12;  // sin(theta)/rho -> dtheta/drho there
  *on_axis = axis;
  const double irs = 1 / (axis ? 1.0 : rho);
  const double s = axis ? dtheta : st * irs;                          // sin(theta) / rho
  const double ds = axis ? 0.0 : (ct * dtheta - st * irs) * irs;      // d s / d rho
  const double ca = axis ? 0.0 : a * irs, cb = axis ? 0.0 : b * irs;  // d rho / da, d rho / db
  return {{axis ? 0.0 : s * a, axis ? 0.0 : s * b, axis ? -1.0 : -ct},
          {s + a * ds * ca, b * ds * ca, st * dtheta * ca},
          {a * ds * cb, s + b * ds * cb, st * dtheta * cb}};
}

// The inverse: polar angle from -z of a camera-space vector, and the unit azimuth (a, b) (zero
// on the axis).
double polar_angle(const Vec3& v, Vec2* azimuth);

// Origins on a segment: p = center + (t - 1/2) edge, with t = u (along_v false) or v (true). No
// normal. A single point when edge is zero.
std::unique_ptr<OrgFunction> make_segment_org(Vec3 center, Vec3 edge, bool along_v);

// A longitude or latitude range in degrees, [low, high], read and checked from `key`; stored in
// radians. Longitude: u = 0 is `low`. Latitude: v = 0 (the top) is `high`.
struct AngleRange {
  double lo = 0, hi = 0;  // radians
  double span() const { return hi - lo; }
};
AngleRange read_angle_range(const ParamValues& v, std::string_view key, double limit_deg);

// u for a longitude (radians), trying lon and lon +- 2 pi; every candidate inside [0, 1] is
// appended (a full-turn range gives both u = 0 and u = 1 on the seam). Returns the count.
int longitude_to_u(double lon, const AngleRange& r, double out[3]);

// Whether an image position lies in [0,1]^2 (with a rounding tolerance, then clamped).
bool clamp_to_image(Vec2* uv);

// Which tile of a cols x rows grid holds image position uv, and the position inside it. Indices
// are clamped so positions slightly outside [0,1]^2 (differentials) stay in an edge tile.
struct TileCoord {
  int col = 0, row = 0;  // row 0 = the top row of the image
  Vec2 st;               // position inside the tile, [0,1]^2, t downward
};
// Inline: the cubemap calls it per ray (the light-field tiles have a vectorized copy of it).
inline TileCoord tile_of(Vec2 uv, int cols, int rows) {
  TileCoord t;
  const double x = uv.x * cols, y = uv.y * rows;
  // floor, clamped; a NaN position lands in tile 0 and is rejected by the caller's checks.
  // Clamping first makes truncation equal floor (and skips the libm call floor is on x86-64).
  t.col = int(std::isfinite(x) ? std::clamp(x, 0.0, double(cols - 1)) : 0.0);
  t.row = int(std::isfinite(y) ? std::clamp(y, 0.0, double(rows - 1)) : 0.0);
  t.st = {x - t.col, y - t.row};
  return t;
}

// A closed-form inverse given as a lambda (camera-space point -> image positions).
template <class F>
class LambdaInverse final : public InverseMap {
 public:
  explicit LambdaInverse(F f) : f_(std::move(f)) {}
  std::vector<Vec2> project(const Vec3& p) const override { return f_(p); }

 private:
  F f_;
};
template <class F>
std::unique_ptr<InverseMap> make_inverse(F f) {
  return std::make_unique<LambdaInverse<F>>(std::move(f));
}

}  // namespace anamorph
