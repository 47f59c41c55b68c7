// Dual numbers: a value and its derivative along one direction (forward-mode automatic
// differentiation). Arithmetic on them carries the derivative exactly (no step, no truncation
// error). Vec3T<Dual> uses Vec3T's operators; length and normalize have their own names here
// (vec.h's call std::sqrt).
#pragma once

#include <cmath>

#include "math/vec.h"

namespace anamorph {

struct Dual {
  double v = 0, d = 0;  // value, derivative
  constexpr Dual() = default;
  constexpr Dual(double value, double derivative = 0) : v(value), d(derivative) {}
};

constexpr Dual operator+(Dual a, Dual b) { return {a.v + b.v, a.d + b.d}; }
constexpr Dual operator-(Dual a, Dual b) { return {a.v - b.v, a.d - b.d}; }
constexpr Dual operator-(Dual a) { return {-a.v, -a.d}; }
constexpr Dual operator*(Dual a, Dual b) { return {a.v * b.v, a.d * b.v + a.v * b.d}; }
constexpr Dual operator/(Dual a, Dual b) {
  return {a.v / b.v, (a.d * b.v - a.v * b.d) / (b.v * b.v)};
}
inline Dual& operator+=(Dual& a, Dual b) { return a = a + b; }
inline Dual sqrt(Dual a) {
  const double s = std::sqrt(a.v);
  return {s, a.d / (2 * s)};
}

using DVec3 = Vec3T<Dual>;
using DVec2 = Vec2T<Dual>;

inline DVec3 dual(const Vec3& v, const Vec3& d = {}) {
  return {{v.x, d.x}, {v.y, d.y}, {v.z, d.z}};
}
inline Vec3 dual_value(const DVec3& a) { return {a.x.v, a.y.v, a.z.v}; }
inline Vec3 dual_derivative(const DVec3& a) { return {a.x.d, a.y.d, a.z.d}; }
inline Dual dual_length(const DVec3& a) { return sqrt(dot(a, a)); }
inline DVec3 dual_normalize(const DVec3& a) { return a / dual_length(a); }

}  // namespace anamorph
