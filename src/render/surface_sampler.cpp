#include "render/surface_sampler.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace anamorph {

namespace {

Vec3 axis_vector(int axis, double s) {
  Vec3 v;
  v[axis] = s;
  return v;
}

}  // namespace

SurfaceSampler::SurfaceSampler(const Accel::Record& r, bool inward) : inward_(inward) {
  bool underflow = false;  // an analytic part of positive size whose area is 0 in double
  switch (r.kind) {
    case Accel::Record::Kind::FlatMesh:
      add_mesh(*r.mesh);
      break;
    case Accel::Record::Kind::Instance:
      for (const auto& m : r.proto->meshes) add_mesh(m);
      world_from_object_ = r.world_from_object, identity_ = false;
      break;
    case Accel::Record::Kind::Shape:
      world_from_object_ = r.world_from_object, identity_ = false;
      underflow = !add_shape(*r.shape);
      break;
  }
  if (!(total_ > 0))
    throw std::invalid_argument(underflow
                                    ? "its surface area underflows to 0 (too small for double "
                                      "precision)"
                                    : "it has no surface area");
  if (!std::isfinite(total_))
    throw std::invalid_argument("its surface area overflows (too large for double precision)");
  if (!identity_) {
    const Vec3 x = world_from_object_.vector({1, 0, 0}), y = world_from_object_.vector({0, 1, 0}),
               z = world_from_object_.vector({0, 0, 1});
    det_ = std::abs(dot(x, cross(y, z)));
  }
}

// A piece of the given area, unless the area is 0 (then false).
bool SurfaceSampler::add(const Piece& p, double area) {
  if (!(area > 0)) return false;
  pieces_.push_back(p);
  total_ += area;
  cdf_.push_back(total_);
  return true;
}

void SurfaceSampler::add_mesh(const TriangleMesh& m) {
  for (size_t t = 0; t < m.triangle_count(); ++t) {
    const Vec3 a(m.positions[m.indices[3 * t]]), b(m.positions[m.indices[3 * t + 1]]),
        c(m.positions[m.indices[3 * t + 2]]);
    add({Part::Triangle, a, b, c}, 0.5 * length(cross(b - a, c - a)));
  }
}

// The shape's pieces in object space; false when one of positive size has an area of 0 in
// double precision.
bool SurfaceSampler::add_shape(const AnalyticShape& s) {
  bool ok = true;
  switch (s.kind) {
    case AnalyticShape::Kind::Plane:
      throw std::invalid_argument("an infinite plane has no finite area");
    case AnalyticShape::Kind::Sphere:
      return add({Part::Sphere, {}, {}, {}, s.radius}, 4 * kPi * s.radius * s.radius);
    case AnalyticShape::Kind::Disk:
      return add({Part::Disk, {}, {}, {}, s.radius, 0, 1, 1}, kPi * s.radius * s.radius);
    case AnalyticShape::Kind::Cylinder:
      ok &=
          add({Part::CylinderSide, {}, {}, {}, s.radius, s.height}, 2 * kPi * s.radius * s.height);
      if (s.capped) {
        ok &= add({Part::Disk, {}, {}, {}, s.radius, 0, -1, 1}, kPi * s.radius * s.radius);
        ok &= add({Part::Disk, {}, {}, {}, s.radius, s.height, 1, 1}, kPi * s.radius * s.radius);
      }
      return ok;
    case AnalyticShape::Kind::Rectangle: {
      Piece p{Part::BoxFace, {-0.5, 0, -0.5}, {0, 0, 1}, {1, 0, 0}};
      p.sign = 1, p.axis = 1;
      return add(p, 1);
    }
    case AnalyticShape::Kind::Box:
      for (int axis = 0; axis < 3; ++axis)
        for (double sign : {-1.0, 1.0}) {
          const int i = (axis + 1) % 3, j = (axis + 2) % 3;
          Piece p{Part::BoxFace, {}, {}, {}};
          p.a = axis_vector(axis, sign * s.size[axis] / 2) - axis_vector(i, s.size[i] / 2) -
                axis_vector(j, s.size[j] / 2);
          p.b = axis_vector(i, s.size[i]), p.c = axis_vector(j, s.size[j]);
          p.sign = sign, p.axis = axis;
          ok &= add(p, s.size[i] * s.size[j]);
        }
      return ok;
  }
  return ok;
}

SurfacePoint SurfaceSampler::local(const Piece& q, double u1, double u2) const {
  switch (q.part) {
    case Part::Triangle: {
      const double s = std::sqrt(u1), b0 = 1 - s, b1 = u2 * s;
      return {q.a * b0 + q.b * b1 + q.c * (1 - b0 - b1), normalize(cross(q.b - q.a, q.c - q.a)), 1};
    }
    case Part::Sphere: {
      const double z = 1 - 2 * u1, rr = std::sqrt(std::max(0.0, 1 - z * z)), phi = 2 * kPi * u2;
      const Vec3 n{rr * std::cos(phi), rr * std::sin(phi), z};
      return {n * q.r, n, 1};
    }
    case Part::Disk: {
      const double rr = q.r * std::sqrt(u1), phi = 2 * kPi * u2;
      return {{rr * std::cos(phi), q.h, rr * std::sin(phi)}, {0, q.sign, 0}, 1};
    }
    case Part::CylinderSide: {
      const double phi = 2 * kPi * u2;
      const Vec3 n{std::cos(phi), 0, std::sin(phi)};
      return {Vec3{n.x * q.r, u1 * q.h, n.z * q.r}, n, 1};
    }
    case Part::BoxFace:
      return {q.a + q.b * u1 + q.c * u2, axis_vector(q.axis, q.sign), 1};
  }
  return {};
}

SurfacePoint SurfaceSampler::sample(double u1, double u2) const {
  const double target = u1 * total_;
  const size_t k = std::min(
      size_t(std::upper_bound(cdf_.begin(), cdf_.end(), target) - cdf_.begin()), cdf_.size() - 1);
  const double lo = k ? cdf_[k - 1] : 0.0, hi = cdf_[k];
  const double v1 = std::clamp((target - lo) / (hi - lo), 0.0, 1.0 - 1e-16);
  SurfacePoint s = local(pieces_[k], v1, u2);
  double scale = 1;
  if (!identity_) {
    const Vec3 m = world_from_object_.normal(s.n);  // M^-T n: its length * |det M| = area scale
    scale = det_ * length(m);
    s.p = world_from_object_.point(s.p);
    s.n = normalize(m);
  }
  if (inward_) s.n = -s.n;
  s.weight = total_ * scale;
  return s;
}

MeasurableSurface measurable_surface(const Accel::Record& r, bool inward) {
  MeasurableSurface m;
  try {
    m.sampler.emplace(r, inward);
  } catch (const std::invalid_argument& e) {
    m.problem = e.what();
    return m;
  }
  m.reference = m.sampler->sample(0.5, 0.5).weight;
  if (!std::isnormal(m.reference)) {
    m.problem = m.reference > 1
                    ? "its transform makes its surface area overflow (too large for double "
                      "precision)"
                    : "its transform makes its surface area underflow (too small for double "
                      "precision)";
    m.sampler.reset();
  }
  return m;
}

}  // namespace anamorph
