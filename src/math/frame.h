// Orthonormal frames. Used for shading (local z = normal) and for camera orientation.
#pragma once

#include "math/vec.h"

namespace anamorph {

struct Frame {
  Vec3 s{1, 0, 0}, t{0, 1, 0}, n{0, 0, 1};

  // Builds a frame around unit n without branches that flip (Duff et al. 2017).
  static Frame from_normal(const Vec3& n) {
    Frame f;
    f.n = n;
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z);
    const double b = n.x * n.y * a;
    f.s = {1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x};
    f.t = {b, sign + n.y * n.y * a, -n.y};
    return f;
  }
  Vec3 to_local(const Vec3& v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
  Vec3 to_world(const Vec3& v) const { return s * v.x + t * v.y + n * v.z; }
};

}  // namespace anamorph
