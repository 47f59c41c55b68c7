// What accel.cpp (building) and accel_query.cpp (the queries) share, and nothing else sees.
#pragma once

#include "accel/accel.h"
#include "accel/shapes.h"

namespace anamorph::accel_detail {

// Geometry masks, one per material class: opaque, transmitting (Whitted's see-through), alpha
// blended, and both. A shadow ray that passes one set of surfaces (Accel::ShadowSet) first asks
// only the geometry outside the set (any-hit), then walks the set's members; every other ray asks
// all.
constexpr unsigned kOpaque = 1, kSeeThrough = 2, kBlend = 4, kBlendSeeThrough = 8;
constexpr unsigned kAll = 0xFFFFFFFF;
// The members of each set, by ShadowSet's value: Whitted's see-through surfaces (transmitting
// or blended), the path tracer's (blended; its paths find the light through glass themselves).
constexpr unsigned kSetMembers[2] = {kSeeThrough | kBlend | kBlendSeeThrough,
                                     kBlend | kBlendSeeThrough};
// What stops a set's shadow rays: every class outside the set.
constexpr unsigned set_blockers(int set) {
  return (kOpaque | kSeeThrough | kBlend | kBlendSeeThrough) & ~kSetMembers[set];
}

// Where the float ray (o, d) meets a shape's record in (tmin, tmax), in double precision in the
// shape's own space; false if nowhere. (The intersection callbacks and the unbounded shapes
// beside the BVH both ask this.)
inline bool shape_t(const Accel::Record& rec, const Vec3& o, const Vec3& d, double tmin,
                    double tmax, double* t) {
  const Vec3 oo = rec.object_from_world.point(o), od = rec.object_from_world.vector(d);
  return intersect_shape(*rec.shape, oo, od, tmin, tmax, t);
}

}  // namespace anamorph::accel_detail
