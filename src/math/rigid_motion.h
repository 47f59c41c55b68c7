// Interpolation between two affine transforms (camera motion blur): each is split into
// translation, rotation (quaternion, slerped) and per-axis scale; shear is not kept.
#pragma once

#include "math/transform.h"

namespace anamorph {

class RigidMotion {
 public:
  RigidMotion() = default;
  RigidMotion(const Transform& a, const Transform& b);
  Transform at(double t) const;  // t in [0, 1]

 private:
  struct Parts {
    Vec3 translation, scale{1, 1, 1};
    double q[4] = {1, 0, 0, 0};  // w, x, y, z
  };
  static Parts split(const Transform& m);
  Parts a_, b_;
};

}  // namespace anamorph
