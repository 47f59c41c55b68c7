#include "math/transform.h"

#include <cmath>

namespace anamorph {

Mat4 transpose(const Mat4& a) {
  Mat4 r;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) r.m[i][j] = a.m[j][i];
  return r;
}

// Gauss-Jordan elimination with partial pivoting.
Mat4 inverse(const Mat4& a, bool* ok) {
  double w[4][8];
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      w[i][j] = a.m[i][j];
      w[i][j + 4] = (i == j) ? 1.0 : 0.0;
    }
  for (int c = 0; c < 4; ++c) {
    int piv = c;
    for (int r = c + 1; r < 4; ++r)
      if (std::abs(w[r][c]) > std::abs(w[piv][c])) piv = r;
    if (std::abs(w[piv][c]) < 1e-300) {
      if (ok) *ok = false;
      return Mat4::identity();
    }
    if (piv != c)
      for (int j = 0; j < 8; ++j) std::swap(w[c][j], w[piv][j]);
    const double d = 1.0 / w[c][c];
    for (int j = 0; j < 8; ++j) w[c][j] *= d;
    for (int r = 0; r < 4; ++r) {
      if (r == c) continue;
      const double f = w[r][c];
      if (f == 0) continue;
      for (int j = 0; j < 8; ++j) w[r][j] -= f * w[c][j];
    }
  }
  Mat4 r;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) r.m[i][j] = w[i][j + 4];
  if (ok) *ok = true;
  return r;
}

Transform::Transform(const Mat4& m) : m_(m), inv_(anamorph::inverse(m)), kind_(classify(m)) {}

Transform Transform::translate(const Vec3& t) {
  Mat4 m = Mat4::identity(), i = Mat4::identity();
  for (int k = 0; k < 3; ++k) {
    m.m[k][3] = t[k];
    i.m[k][3] = -t[k];
  }
  return {m, i};
}

Transform Transform::scale(const Vec3& s) {
  Mat4 m = Mat4::identity(), i = Mat4::identity();
  for (int k = 0; k < 3; ++k) {
    m.m[k][k] = s[k];
    i.m[k][k] = 1.0 / s[k];
  }
  return {m, i};
}

Transform Transform::rotate(double deg, const Vec3& axis) {
  const Vec3 a = normalize(axis);
  const double s = std::sin(radians(deg)), c = std::cos(radians(deg));
  Mat4 m = Mat4::identity();
  m.m[0][0] = a.x * a.x + (1 - a.x * a.x) * c;
  m.m[0][1] = a.x * a.y * (1 - c) - a.z * s;
  m.m[0][2] = a.x * a.z * (1 - c) + a.y * s;
  m.m[1][0] = a.x * a.y * (1 - c) + a.z * s;
  m.m[1][1] = a.y * a.y + (1 - a.y * a.y) * c;
  m.m[1][2] = a.y * a.z * (1 - c) - a.x * s;
  m.m[2][0] = a.x * a.z * (1 - c) - a.y * s;
  m.m[2][1] = a.y * a.z * (1 - c) + a.x * s;
  m.m[2][2] = a.z * a.z + (1 - a.z * a.z) * c;
  return {m, anamorph::transpose(m)};
}

Transform Transform::look_at(const Vec3& from, const Vec3& to, const Vec3& up) {
  const Vec3 f = normalize(to - from);
  const Vec3 r = normalize(cross(f, up));
  const Vec3 u = cross(r, f);
  Mat4 m = Mat4::identity();
  for (int k = 0; k < 3; ++k) {
    m.m[k][0] = r[k];
    m.m[k][1] = u[k];
    m.m[k][2] = -f[k];
    m.m[k][3] = from[k];
  }
  return Transform(m);
}

Bounds3 Transform::bounds(const Bounds3& b) const {
  Bounds3 r;
  if (b.empty()) return r;
  for (int i = 0; i < 8; ++i)
    r.extend(
        point({(i & 1) ? b.hi.x : b.lo.x, (i & 2) ? b.hi.y : b.lo.y, (i & 4) ? b.hi.z : b.lo.z}));
  return r;
}

bool Transform::swaps_handedness() const {
  const auto& a = m_.m;
  const double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                     a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                     a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
  return det < 0;
}

}  // namespace anamorph
