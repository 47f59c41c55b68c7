// Affine transforms as 4x4 matrices. Names follow pbrt: `world_from_object` maps object-space
// points into world space, so chains read right to left.
#pragma once

#include <array>

#include "math/vec.h"

namespace anamorph {

struct Mat4 {
  std::array<std::array<double, 4>, 4> m{};
  static Mat4 identity() {
    Mat4 r;
    for (int i = 0; i < 4; ++i) r.m[i][i] = 1;
    return r;
  }
  Mat4 operator*(const Mat4& b) const {
    Mat4 r;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) {
        double s = 0;
        for (int k = 0; k < 4; ++k) s += m[i][k] * b.m[k][j];
        r.m[i][j] = s;
      }
    return r;
  }
  bool operator==(const Mat4&) const = default;
};

Mat4 inverse(const Mat4& a, bool* ok = nullptr);
Mat4 transpose(const Mat4& a);

class Transform {
 public:
  Transform() : m_(Mat4::identity()), inv_(Mat4::identity()), kind_(Kind::Identity) {}
  explicit Transform(const Mat4& m);
  Transform(const Mat4& m, const Mat4& inv) : m_(m), inv_(inv), kind_(classify(m)) {}

  static Transform translate(const Vec3& t);
  static Transform scale(const Vec3& s);
  static Transform rotate(double degrees, const Vec3& axis);
  // Camera-style frame: maps local (x right, y up, -z forward) to world.
  static Transform look_at(const Vec3& from, const Vec3& to, const Vec3& up);

  Transform operator*(const Transform& b) const { return {m_ * b.m_, b.inv_ * inv_}; }
  Transform inverse() const { return {inv_, m_}; }
  const Mat4& matrix() const { return m_; }
  const Mat4& inverse_matrix() const { return inv_; }
  bool is_identity() const { return m_ == Mat4::identity(); }

  // Most objects are placed by a translation alone, or not moved at all (a sphere by its
  // center, a floor): those skip the products with 0 and 1, which cost the intersection
  // callbacks and hit records a fifth of their time. (Identical results for finite inputs, up
  // to the sign of a zero.)
  Vec3 point(const Vec3& p) const {
    const auto& a = m_.m;
    if (kind_ == Kind::Identity) return p;
    if (kind_ == Kind::Translation) return {p.x + a[0][3], p.y + a[1][3], p.z + a[2][3]};
    Vec3 r{a[0][0] * p.x + a[0][1] * p.y + a[0][2] * p.z + a[0][3],
           a[1][0] * p.x + a[1][1] * p.y + a[1][2] * p.z + a[1][3],
           a[2][0] * p.x + a[2][1] * p.y + a[2][2] * p.z + a[2][3]};
    if (kind_ == Kind::Affine) return r;
    const double w = a[3][0] * p.x + a[3][1] * p.y + a[3][2] * p.z + a[3][3];
    return w == 1 ? r : r / w;
  }
  Vec3 vector(const Vec3& v) const {
    if (kind_ <= Kind::Translation) return v;
    const auto& a = m_.m;
    return {a[0][0] * v.x + a[0][1] * v.y + a[0][2] * v.z,
            a[1][0] * v.x + a[1][1] * v.y + a[1][2] * v.z,
            a[2][0] * v.x + a[2][1] * v.y + a[2][2] * v.z};
  }
  // Normals transform with the inverse transpose.
  Vec3 normal(const Vec3& n) const {
    if (kind_ <= Kind::Translation) return n;
    const auto& a = inv_.m;
    return {a[0][0] * n.x + a[1][0] * n.y + a[2][0] * n.z,
            a[0][1] * n.x + a[1][1] * n.y + a[2][1] * n.z,
            a[0][2] * n.x + a[1][2] * n.y + a[2][2] * n.z};
  }
  Bounds3 bounds(const Bounds3& b) const;
  // True when the linear part flips orientation (negative determinant).
  bool swaps_handedness() const;

 private:
  enum class Kind : unsigned char { Identity, Translation, Affine, Projective };
  static Kind classify(const Mat4& m) {
    const auto& a = m.m;
    if (a[3][0] != 0 || a[3][1] != 0 || a[3][2] != 0 || a[3][3] != 1) return Kind::Projective;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (a[i][j] != (i == j ? 1 : 0)) return Kind::Affine;
    return a[0][3] == 0 && a[1][3] == 0 && a[2][3] == 0 ? Kind::Identity : Kind::Translation;
  }
  Mat4 m_, inv_;
  Kind kind_;
};

}  // namespace anamorph
