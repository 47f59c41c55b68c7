#include "scene/shape.h"

namespace anamorph {

namespace {

// An infinite plane is infinite (accel tests it beside the BVH); its bounds, which stand for it
// where a finite box is needed (the scene's extent, the editor's boxes), are this square.
constexpr double kPlaneExtent = 1e6;

}  // namespace

Bounds3 shape_object_bounds(const AnalyticShape& s) {
  Bounds3 b;
  switch (s.kind) {
    case AnalyticShape::Kind::Sphere:
      b.extend(Vec3(-s.radius));
      b.extend(Vec3(s.radius));
      break;
    case AnalyticShape::Kind::Plane:
      b.extend({-kPlaneExtent, -1e-6, -kPlaneExtent});
      b.extend({kPlaneExtent, 1e-6, kPlaneExtent});
      break;
    case AnalyticShape::Kind::Disk:
      b.extend({-s.radius, -1e-6, -s.radius});
      b.extend({s.radius, 1e-6, s.radius});
      break;
    case AnalyticShape::Kind::Rectangle:
      b.extend({-0.5, -1e-6, -0.5});
      b.extend({0.5, 1e-6, 0.5});
      break;
    case AnalyticShape::Kind::Box:
      b.extend(s.size * -0.5);
      b.extend(s.size * 0.5);
      break;
    case AnalyticShape::Kind::Cylinder:
      b.extend({-s.radius, 0, -s.radius});
      b.extend({s.radius, s.height, s.radius});
      break;
  }
  return b;
}

}  // namespace anamorph
