// Analytic primitives, intersected exactly (Embree user geometry). Each lives in its own object
// space (unit-sized, described below) placed by `world_from_object`.
#pragma once

#include <string>

#include "math/transform.h"

namespace anamorph {

struct AnalyticShape {
  enum class Kind {
    Sphere,     // center (0,0,0), radius `radius`
    Plane,      // infinite plane y = 0, normal +y
    Box,        // axis-aligned box [-size/2, size/2]
    Cylinder,   // axis y, radius `radius`, y in [0, height], open or capped
    Disk,       // y = 0 plane, normal +y, radius `radius`
    Rectangle,  // y = 0 plane, normal +y, x and z in [-1/2, 1/2] (shaped by its transform)
  };
  Kind kind = Kind::Sphere;
  double radius = 1;
  Vec3 size{1, 1, 1};
  double height = 1;
  bool capped = true;
  uint32_t material = 0;
  Transform world_from_object;
  std::string name;
};

// Object-space bounds; the infinite plane gets a large finite square (its extent where one is
// needed, the scene's bounds and the editor's boxes; it is not clipped to it).
Bounds3 shape_object_bounds(const AnalyticShape& s);

}  // namespace anamorph
