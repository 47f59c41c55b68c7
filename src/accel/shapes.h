// Exact ray intersection and surface parameterization of analytic shapes in their object space
// (see scene/shape.h for each shape's canonical placement).
#pragma once

#include "math/vec.h"
#include "scene/shape.h"

namespace anamorph {

// Nearest t in (tmin, tmax) where o + t d meets the shape; false if none.
bool intersect_shape(const AnalyticShape& s, const Vec3& o, const Vec3& d, double tmin, double tmax,
                     double* t);

struct ShapeSurface {
  Vec3 n;           // outward unit normal (object space)
  Vec2 uv;          // parameterization
  Vec3 dpdu, dpdv;  // derivatives w.r.t. uv (object space)
};
ShapeSurface shape_surface(const AnalyticShape& s, const Vec3& p);
// Just shape_surface(s, p).n, without the parameterization (a sphere's uv costs an atan2 and
// an acos).
Vec3 shape_normal(const AnalyticShape& s, const Vec3& p);

}  // namespace anamorph
