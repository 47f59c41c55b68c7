// Small fixed-size vectors. Vec3 (double) is the working type for cameras, geometry set-up and
// shading; Vec3f (float) is for large buffers (vertices, film) that Embree or memory want small.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace anamorph {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kInvPi = 1.0 / kPi;
inline constexpr double kInf = std::numeric_limits<double>::infinity();

inline double radians(double deg) { return deg * (kPi / 180.0); }
inline double degrees(double rad) { return rad * (180.0 / kPi); }

template <class T>
struct Vec2T {
  T x = 0, y = 0;
  constexpr Vec2T() = default;
  constexpr Vec2T(T x_, T y_) : x(x_), y(y_) {}
  constexpr T operator[](int i) const { return i == 0 ? x : y; }
  constexpr T& operator[](int i) { return i == 0 ? x : y; }
  constexpr Vec2T operator+(Vec2T b) const { return {x + b.x, y + b.y}; }
  constexpr Vec2T operator-(Vec2T b) const { return {x - b.x, y - b.y}; }
  constexpr Vec2T operator*(T s) const { return {x * s, y * s}; }
  constexpr Vec2T operator/(T s) const { return {x / s, y / s}; }
  constexpr Vec2T operator-() const { return {-x, -y}; }
  constexpr bool operator==(const Vec2T&) const = default;
};

template <class T>
struct Vec3T {
  T x = 0, y = 0, z = 0;
  constexpr Vec3T() = default;
  constexpr Vec3T(T x_, T y_, T z_) : x(x_), y(y_), z(z_) {}
  constexpr explicit Vec3T(T s) : x(s), y(s), z(s) {}
  template <class U>
  constexpr explicit Vec3T(const Vec3T<U>& o) : x(T(o.x)), y(T(o.y)), z(T(o.z)) {}

  constexpr T operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr T& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr Vec3T operator+(const Vec3T& b) const { return {x + b.x, y + b.y, z + b.z}; }
  constexpr Vec3T operator-(const Vec3T& b) const { return {x - b.x, y - b.y, z - b.z}; }
  constexpr Vec3T operator*(const Vec3T& b) const { return {x * b.x, y * b.y, z * b.z}; }
  constexpr Vec3T operator/(const Vec3T& b) const { return {x / b.x, y / b.y, z / b.z}; }
  constexpr Vec3T operator*(T s) const { return {x * s, y * s, z * s}; }
  constexpr Vec3T operator/(T s) const { return {x / s, y / s, z / s}; }
  constexpr Vec3T operator-() const { return {-x, -y, -z}; }
  constexpr Vec3T& operator+=(const Vec3T& b) {
    x += b.x;
    y += b.y;
    z += b.z;
    return *this;
  }
  constexpr Vec3T& operator-=(const Vec3T& b) {
    x -= b.x;
    y -= b.y;
    z -= b.z;
    return *this;
  }
  constexpr Vec3T& operator*=(const Vec3T& b) {
    x *= b.x;
    y *= b.y;
    z *= b.z;
    return *this;
  }
  constexpr Vec3T& operator*=(T s) {
    x *= s;
    y *= s;
    z *= s;
    return *this;
  }
  constexpr Vec3T& operator/=(T s) {
    x /= s;
    y /= s;
    z /= s;
    return *this;
  }
  constexpr bool operator==(const Vec3T&) const = default;
};

template <class T>
constexpr Vec3T<T> operator*(T s, const Vec3T<T>& v) {
  return v * s;
}
template <class T>
constexpr Vec2T<T> operator*(T s, const Vec2T<T>& v) {
  return v * s;
}

using Vec2 = Vec2T<double>;
using Vec3 = Vec3T<double>;
using Vec2f = Vec2T<float>;
using Vec3f = Vec3T<float>;
using Color = Vec3;  // linear RGB

template <class T>
constexpr T dot(const Vec3T<T>& a, const Vec3T<T>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class T>
constexpr T dot(const Vec2T<T>& a, const Vec2T<T>& b) {
  return a.x * b.x + a.y * b.y;
}
template <class T>
constexpr Vec3T<T> cross(const Vec3T<T>& a, const Vec3T<T>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class T>
inline T length(const Vec3T<T>& v) {
  return std::sqrt(dot(v, v));
}
template <class T>
inline T length(const Vec2T<T>& v) {
  return std::sqrt(dot(v, v));
}
template <class T>
constexpr T length_squared(const Vec3T<T>& v) {
  return dot(v, v);
}
template <class T>
inline Vec3T<T> normalize(const Vec3T<T>& v) {
  return v / length(v);
}
template <class T>
constexpr Vec3T<T> min(const Vec3T<T>& a, const Vec3T<T>& b) {
  return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
template <class T>
constexpr Vec3T<T> max(const Vec3T<T>& a, const Vec3T<T>& b) {
  return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}
template <class T>
constexpr T max_component(const Vec3T<T>& v) {
  return std::max(v.x, std::max(v.y, v.z));
}
template <class T>
constexpr T min_component(const Vec3T<T>& v) {
  return std::min(v.x, std::min(v.y, v.z));
}
template <class T>
inline bool is_finite(const Vec3T<T>& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
template <class T>
constexpr Vec3T<T> lerp(T t, const Vec3T<T>& a, const Vec3T<T>& b) {
  return a * (T(1) - t) + b * t;
}
inline double luminance(const Color& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

// Reflect v about n (both pointing away from the surface).
inline Vec3 reflect(const Vec3& wo, const Vec3& n) { return -wo + n * (2 * dot(wo, n)); }

// Axis-aligned bounding box.
struct Bounds3 {
  Vec3 lo{kInf, kInf, kInf};
  Vec3 hi{-kInf, -kInf, -kInf};
  void extend(const Vec3& p) {
    lo = min(lo, p);
    hi = max(hi, p);
  }
  void extend(const Bounds3& b) {
    lo = min(lo, b.lo);
    hi = max(hi, b.hi);
  }
  bool empty() const { return lo.x > hi.x; }
  Vec3 center() const { return (lo + hi) * 0.5; }
  Vec3 diagonal() const { return hi - lo; }
};

}  // namespace anamorph
