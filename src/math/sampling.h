// Warping functions from the unit square to common domains, with their densities. Angles go
// through sincos_poly (inline, a few ulp): glibc's sincos call was a tenth of a path-traced
// render's time.
#pragma once

#include <cmath>

#include "math/fast_trig.h"
#include "math/vec.h"

namespace anamorph {

// Concentric disk mapping (Shirley-Chiu): preserves stratification.
inline Vec2 sample_disk_concentric(Vec2 u) {
  const Vec2 o = u * 2.0 - Vec2{1, 1};
  if (o.x == 0 && o.y == 0) return {0, 0};
  double r, theta;
  if (std::abs(o.x) > std::abs(o.y)) {
    r = o.x;
    theta = (kPi / 4) * (o.y / o.x);
  } else {
    r = o.y;
    theta = kPi / 2 - (kPi / 4) * (o.x / o.y);
  }
  double s, c;
  sincos_poly(theta, &s, &c);
  return {r * c, r * s};
}

inline Vec3 sample_cosine_hemisphere(Vec2 u) {
  const Vec2 d = sample_disk_concentric(u);
  const double z = std::sqrt(std::max(0.0, 1 - d.x * d.x - d.y * d.y));
  return {d.x, d.y, z};
}
inline double cosine_hemisphere_pdf(double cos_theta) { return cos_theta * kInvPi; }

inline Vec3 sample_uniform_sphere(Vec2 u) {
  const double z = 1 - 2 * u.x;
  const double r = std::sqrt(std::max(0.0, 1 - z * z));
  double s, c;
  sincos_poly(2 * kPi * u.y, &s, &c);
  return {r * c, r * s, z};
}
inline double uniform_sphere_pdf() { return 1.0 / (4 * kPi); }

// Uniform direction inside a cone around +z with cos of half-angle cos_max.
inline Vec3 sample_uniform_cone(Vec2 u, double cos_max) {
  const double cos_t = (1 - u.x) + u.x * cos_max;
  const double sin_t = std::sqrt(std::max(0.0, 1 - cos_t * cos_t));
  double s, c;
  sincos_poly(2 * kPi * u.y, &s, &c);
  return {c * sin_t, s * sin_t, cos_t};
}
inline double uniform_cone_pdf(double cos_max) { return 1.0 / (2 * kPi * (1 - cos_max)); }

// Uniform point on a triangle as barycentrics (b0, b1).
inline Vec2 sample_uniform_triangle(Vec2 u) {
  const double su = std::sqrt(u.x);
  return {1 - su, u.y * su};
}

inline double power_heuristic(double fpdf, double gpdf) {
  const double f = fpdf * fpdf, g = gpdf * gpdf;
  return (f + g) > 0 ? f / (f + g) : 0.0;
}

}  // namespace anamorph
