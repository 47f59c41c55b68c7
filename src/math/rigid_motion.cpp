#include "math/rigid_motion.h"

#include <cmath>

namespace anamorph {

RigidMotion::Parts RigidMotion::split(const Transform& t) {
  Parts p;
  const auto& m = t.matrix().m;
  p.translation = {m[0][3], m[1][3], m[2][3]};
  Vec3 col[3];
  for (int c = 0; c < 3; ++c) {
    col[c] = {m[0][c], m[1][c], m[2][c]};
    p.scale[c] = length(col[c]);
    col[c] = col[c] / p.scale[c];
  }
  // Re-orthonormalize (Gram-Schmidt) so the rotation is exact even after rounding.
  col[1] = normalize(col[1] - col[0] * dot(col[0], col[1]));
  col[2] = cross(col[0], col[1]);
  if (t.swaps_handedness()) p.scale[2] = -p.scale[2];
  // Rotation matrix (columns) to quaternion (Shepperd's method).
  const double r00 = col[0].x, r11 = col[1].y, r22 = col[2].z;
  const double tr = r00 + r11 + r22;
  double w, x, y, z;
  if (tr > 0) {
    const double s = std::sqrt(tr + 1) * 2;
    w = 0.25 * s;
    x = (col[1].z - col[2].y) / s;
    y = (col[2].x - col[0].z) / s;
    z = (col[0].y - col[1].x) / s;
  } else if (r00 > r11 && r00 > r22) {
    const double s = std::sqrt(1 + r00 - r11 - r22) * 2;
    w = (col[1].z - col[2].y) / s;
    x = 0.25 * s;
    y = (col[1].x + col[0].y) / s;
    z = (col[2].x + col[0].z) / s;
  } else if (r11 > r22) {
    const double s = std::sqrt(1 + r11 - r00 - r22) * 2;
    w = (col[2].x - col[0].z) / s;
    x = (col[1].x + col[0].y) / s;
    y = 0.25 * s;
    z = (col[2].y + col[1].z) / s;
  } else {
    const double s = std::sqrt(1 + r22 - r00 - r11) * 2;
    w = (col[0].y - col[1].x) / s;
    x = (col[2].x + col[0].z) / s;
    y = (col[2].y + col[1].z) / s;
    z = 0.25 * s;
  }
  p.q[0] = w, p.q[1] = x, p.q[2] = y, p.q[3] = z;
  return p;
}

RigidMotion::RigidMotion(const Transform& a, const Transform& b) : a_(split(a)), b_(split(b)) {
  // Take the short way round.
  double d = 0;
  for (int i = 0; i < 4; ++i) d += a_.q[i] * b_.q[i];
  if (d < 0)
    for (double& c : b_.q) c = -c;
}

Transform RigidMotion::at(double t) const {
  double d = 0;
  for (int i = 0; i < 4; ++i) d += a_.q[i] * b_.q[i];
  double q[4];
  if (d > 0.9995) {
    for (int i = 0; i < 4; ++i) q[i] = a_.q[i] + (b_.q[i] - a_.q[i]) * t;
  } else {
    const double th = std::acos(std::min(1.0, d));
    const double sa = std::sin((1 - t) * th) / std::sin(th), sb = std::sin(t * th) / std::sin(th);
    for (int i = 0; i < 4; ++i) q[i] = a_.q[i] * sa + b_.q[i] * sb;
  }
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  const double w = q[0] / n, x = q[1] / n, y = q[2] / n, z = q[3] / n;
  const Vec3 s = lerp(t, a_.scale, b_.scale), tr = lerp(t, a_.translation, b_.translation);
  Mat4 m = Mat4::identity();
  const double r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                          {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                          {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) m.m[i][j] = r[i][j] * s[j];
    m.m[i][3] = tr[i];
  }
  return Transform(m);
}

}  // namespace anamorph
