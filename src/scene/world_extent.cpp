#include "scene/world_extent.h"

#include <fmt/format.h>

#include <cmath>

#include "math/input_limits.h"

namespace anamorph {

namespace {

bool finite(const Mat4& m) {
  for (const auto& row : m.m)
    for (double x : row)
      if (!std::isfinite(x)) return false;
  return true;
}

}  // namespace

std::string placement_error(const Transform& world_from_object, const Bounds3& object_box) {
  if (!finite(world_from_object.matrix()) || !finite(world_from_object.inverse_matrix()))
    return "the transforms placing it compose to a singular or non-finite one (scale factors "
           "that multiply to zero or to infinity)";
  if (object_box.empty()) return "";
  const Bounds3 b = world_from_object.bounds(object_box);
  if (within_world(b.lo) && within_world(b.hi)) return "";
  const char* axis = "xyz";
  int worst = 0;
  double reach = 0;
  for (const Vec3& p : {b.lo, b.hi})
    for (int a = 0; a < 3; ++a)
      if (!(std::abs(p[a]) <= reach)) reach = std::abs(p[a]), worst = a;
  return fmt::format(
      "it reaches |{}| = {:g}, beyond the {:g} scene units from the origin anamorph renders (see "
      "Coordinates in docs/scene-format.md)",
      axis[worst], reach, kMaxCoordinate);
}

Bounds3 prototype_bounds(const Prototype& p) {
  Bounds3 b;
  for (const TriangleMesh& m : p.meshes)
    for (const Vec3f& v : m.positions) b.extend(Vec3(v));
  return b;
}

}  // namespace anamorph
