// Points spread over one scene object's surface by area, for form factors: the surface of a
// top-level geometry (an analytic shape, a mesh, an instance of a prototype) in world space.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "accel/accel.h"

namespace anamorph {

struct SurfacePoint {
  Vec3 p, n;      // world position and unit normal (the side the surface faces)
  double weight;  // the world area this sample stands for (times the sample count)
};

class SurfaceSampler {
 public:
  // `inward` turns every normal around (an enclosure seen from inside). Throws
  // std::invalid_argument saying why a surface has no finite area (an infinite plane; an area
  // that underflows or overflows double precision).
  SurfaceSampler(const Accel::Record& r, bool inward);

  // The point at random numbers (u1, u2) in [0, 1)^2: u1 chooses where along the surface's
  // cumulative area (stratify it across samples for an even spread), u2 the rest.
  SurfacePoint sample(double u1, double u2) const;

 private:
  enum class Part { Triangle, Sphere, Disk, CylinderSide, BoxFace };
  struct Piece {
    Part part;
    Vec3 a, b, c;  // triangle corners / box face: corner and two edges / unused
    double r = 0, h = 0;
    double sign = 1;  // disk / cap / box face: which way its normal points along its axis
    int axis = 1;     // box face, disk: the axis of the normal (0 x, 1 y, 2 z)
  };
  SurfacePoint local(const Piece& piece, double u1, double u2) const;
  bool add(const Piece& p, double area);
  void add_mesh(const TriangleMesh& m);
  bool add_shape(const AnalyticShape& s);
  std::vector<Piece> pieces_;
  std::vector<double> cdf_;  // cumulative object-space area, last = total_
  double total_ = 0;
  double det_ = 1;  // |det| of the transform's linear part (area scale = det_ |M^-T n|)
  Transform world_from_object_;
  bool identity_ = true, inward_ = false;
};

// Object r's surface for form factors, or why it has none: an infinite plane, an area that
// underflows or overflows double precision in object space or, under its transform, in the
// world. `reference` is the weight of the point at (0.5, 0.5) (a normal, finite number): form
// factors divide weights by it, so that sums of squared weights stay within double precision
// for areas of any size.
struct MeasurableSurface {
  std::optional<SurfaceSampler> sampler;
  double reference = 0;
  std::string problem;  // empty when `sampler` is set
};
MeasurableSurface measurable_surface(const Accel::Record& r, bool inward);

}  // namespace anamorph
