// What accel.cpp (building) and accel_query.cpp (the queries) share, and nothing else sees.
#pragma once

#include "accel/accel.h"
#include "accel/shapes.h"

namespace anamorph::accel_detail {

// Geometry masks: a shadow ray of the Whitted integrator first asks only the opaque geometry
// (kOpaque), then walks the see-through surfaces (kSeeThrough); every other ray asks all.
constexpr unsigned kOpaque = 1, kSeeThrough = 2, kAll = 0xFFFFFFFF;

// Where the float ray (o, d) meets a shape's record in (tmin, tmax), in double precision in the
// shape's own space; false if nowhere. (The intersection callbacks and the unbounded shapes
// beside the BVH both ask this.)
inline bool shape_t(const Accel::Record& rec, const Vec3& o, const Vec3& d, double tmin,
                    double tmax, double* t) {
  const Vec3 oo = rec.object_from_world.point(o), od = rec.object_from_world.vector(d);
  return intersect_shape(*rec.shape, oo, od, tmin, tmax, t);
}

}  // namespace anamorph::accel_detail
