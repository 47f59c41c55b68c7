// Warping functions from the unit square to common domains, with their densities. Angles go
// through sincos_poly (inline, a few ulp): glibc's sincos call was a tenth of a path-traced
// render's time.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

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

// Cones are given by 1 - cos of their half-angle, which stays accurate for the tiny cones small
// or far spheres subtend, where the cosine itself rounds to 1 (and a pdf of 1 / (1 - cos) would
// be infinite).
// 1 - cos of the half-angle of the cone a sphere of squared radius r2 subtends from squared
// distance d2 > r2 (0 when r2 / d2 underflows: no solid angle in double precision).
inline double sphere_cone_one_minus_cos(double r2, double d2) {
  const double s2 = r2 / d2;  // sin^2 of the half-angle; 1 - cos = sin^2 / (1 + cos)
  return s2 / (1 + std::sqrt(std::max(0.0, 1 - s2)));
}
// Uniform direction inside a cone around +z.
inline Vec3 sample_uniform_cone(Vec2 u, double one_minus_cos) {
  const double t = u.x * one_minus_cos;  // 1 - cos of the direction's angle
  const double sin_t = std::sqrt(std::max(0.0, t * (2 - t)));
  double s, c;
  sincos_poly(2 * kPi * u.y, &s, &c);
  return {c * sin_t, s * sin_t, 1 - t};
}
inline double uniform_cone_pdf(double one_minus_cos) { return 1.0 / (2 * kPi * one_minus_cos); }

// Uniform point on a triangle as barycentrics (b0, b1).
inline Vec2 sample_uniform_triangle(Vec2 u) {
  const double su = std::sqrt(u.x);
  return {1 - su, u.y * su};
}

inline double power_heuristic(double fpdf, double gpdf) {
  const double f = fpdf * fpdf, g = gpdf * gpdf;
  if (f + g <= std::numeric_limits<double>::max()) return (f + g) > 0 ? f / (f + g) : 0.0;
  // Squares beyond double precision (a pdf above 1e154, toward a tiny light): the same weight
  // from the ratio of the two pdfs, never inf / inf.
  if (!(fpdf > 0)) return 0.0;
  if (!(gpdf > 0)) return 1.0;
  if (fpdf >= gpdf) {
    const double r = gpdf / fpdf;  // (both infinite: NaN, an even split)
    return r >= 0 ? 1 / (1 + r * r) : 0.5;
  }
  const double r = fpdf / gpdf;
  return r * r / (1 + r * r);
}

}  // namespace anamorph
