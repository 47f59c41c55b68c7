#include "accel/shapes.h"

#include <algorithm>
#include <cmath>

namespace anamorph {

namespace {

// Real roots of a t^2 + b t + c with the cancellation-free formula; false when none.
bool solve_quadratic(double a, double b, double c, double* t0, double* t1) {
  const double disc = b * b - 4 * a * c;
  if (disc < 0 || a == 0) return false;
  const double r = std::sqrt(disc);
  const double q = b < 0 ? -0.5 * (b - r) : -0.5 * (b + r);
  double x0 = q / a, x1 = q != 0 ? c / q : x0;
  if (x0 > x1) std::swap(x0, x1);
  *t0 = x0;
  *t1 = x1;
  return true;
}

bool pick(double t0, double t1, double tmin, double tmax, double* t) {
  if (t0 > tmin && t0 < tmax) return *t = t0, true;
  if (t1 > tmin && t1 < tmax) return *t = t1, true;
  return false;
}

}  // namespace

namespace {

bool intersect_sphere(double radius, const Vec3& o, const Vec3& d, double tmin, double tmax,
                      double* t) {
  // Solve relative to the point on the ray closest to the center for precision far away.
  const double a = dot(d, d);
  const double tc = -dot(o, d) / a;
  const Vec3 pc = o + d * tc;
  const double r2 = radius * radius;
  const double h2 = r2 - dot(pc, pc);
  if (h2 < 0) return false;
  const double h = std::sqrt(h2 / a);
  return pick(tc - h, tc + h, tmin, tmax, t);
}

// The plane y = 0, or the part of it a disk or the unit rectangle covers.
bool intersect_flat(const AnalyticShape& s, const Vec3& o, const Vec3& d, double tmin, double tmax,
                    double* t) {
  if (d.y == 0) return false;
  const double th = -o.y / d.y;
  if (!(th > tmin && th < tmax)) return false;
  const Vec3 p = o + d * th;
  if (s.kind == AnalyticShape::Kind::Disk && p.x * p.x + p.z * p.z > s.radius * s.radius)
    return false;
  if (s.kind == AnalyticShape::Kind::Rectangle && (std::abs(p.x) > 0.5 || std::abs(p.z) > 0.5))
    return false;
  *t = th;
  return true;
}

bool intersect_box(const Vec3& size, const Vec3& o, const Vec3& d, double tmin, double tmax,
                   double* t) {
  // Slabs; t0 is the entry, t1 the exit.
  double t0 = -kInf, t1 = kInf;
  for (int i = 0; i < 3; ++i) {
    const double h = size[i] * 0.5;
    const double inv = 1.0 / d[i];
    double a = (-h - o[i]) * inv, b = (h - o[i]) * inv;
    if (std::isnan(a) || std::isnan(b)) {  // parallel ray on a slab plane
      if (o[i] < -h || o[i] > h) return false;
      continue;
    }
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
  }
  if (t0 > t1) return false;
  return pick(t0, t1, tmin, tmax, t);
}

bool intersect_cylinder(const AnalyticShape& s, const Vec3& o, const Vec3& d, double tmin,
                        double tmax, double* t) {
  double best = tmax;
  bool found = false;
  double t0, t1;
  if (solve_quadratic(d.x * d.x + d.z * d.z, 2 * (o.x * d.x + o.z * d.z),
                      o.x * o.x + o.z * o.z - s.radius * s.radius, &t0, &t1)) {
    for (double tc : {t0, t1}) {
      const double y = o.y + d.y * tc;
      if (tc > tmin && tc < best && y >= 0 && y <= s.height) {
        best = tc;
        found = true;
      }
    }
  }
  if (s.capped && d.y != 0) {
    for (double yc : {0.0, s.height}) {
      const double tc = (yc - o.y) / d.y;
      const Vec3 p = o + d * tc;
      if (tc > tmin && tc < best && p.x * p.x + p.z * p.z <= s.radius * s.radius) {
        best = tc;
        found = true;
      }
    }
  }
  if (found) *t = best;
  return found;
}

}  // namespace

bool intersect_shape(const AnalyticShape& s, const Vec3& o, const Vec3& d, double tmin, double tmax,
                     double* t) {
  switch (s.kind) {
    case AnalyticShape::Kind::Sphere:
      return intersect_sphere(s.radius, o, d, tmin, tmax, t);
    case AnalyticShape::Kind::Plane:
    case AnalyticShape::Kind::Rectangle:
    case AnalyticShape::Kind::Disk:
      return intersect_flat(s, o, d, tmin, tmax, t);
    case AnalyticShape::Kind::Box:
      return intersect_box(s.size, o, d, tmin, tmax, t);
    case AnalyticShape::Kind::Cylinder:
      return intersect_cylinder(s, o, d, tmin, tmax, t);
  }
  return false;
}

namespace {

// The face of a box a point lies on: the axis with the largest relative coordinate.
int box_axis(const AnalyticShape& s, const Vec3& p) {
  int axis = 0;
  double best = -1;
  for (int i = 0; i < 3; ++i) {
    const double rel = std::abs(p[i]) / (s.size[i] * 0.5);
    if (rel > best) best = rel, axis = i;
  }
  return axis;
}

// Whether a point of a capped cylinder lies on a cap (else on the side).
bool on_cylinder_cap(const AnalyticShape& s, const Vec3& p, double rr) {
  const double eps = 1e-9 * std::max(1.0, s.height);
  return s.capped && (p.y <= eps || p.y >= s.height - eps) && rr < s.radius * (1 - 1e-9);
}

}  // namespace

Vec3 shape_normal(const AnalyticShape& s, const Vec3& p) {
  switch (s.kind) {
    case AnalyticShape::Kind::Sphere:
      return normalize(p);
    case AnalyticShape::Kind::Plane:
    case AnalyticShape::Kind::Disk:
    case AnalyticShape::Kind::Rectangle:
      return {0, 1, 0};
    case AnalyticShape::Kind::Box: {
      const int axis = box_axis(s, p);
      Vec3 n{};
      n[axis] = p[axis] >= 0 ? 1 : -1;
      return n;
    }
    case AnalyticShape::Kind::Cylinder: {
      const double rr = std::sqrt(p.x * p.x + p.z * p.z);
      if (on_cylinder_cap(s, p, rr))
        return {0, p.y <= 1e-9 * std::max(1.0, s.height) ? -1.0 : 1.0, 0};
      return rr > 0 ? Vec3{p.x / rr, 0, p.z / rr} : Vec3{1, 0, 0};
    }
  }
  return {0, 1, 0};
}

ShapeSurface shape_surface(const AnalyticShape& s, const Vec3& p) {
  ShapeSurface r;
  r.n = shape_normal(s, p);
  switch (s.kind) {
    case AnalyticShape::Kind::Sphere: {
      const double phi = std::atan2(p.x, p.z);  // longitude around +y
      const double theta = std::acos(std::clamp(p.y / s.radius, -1.0, 1.0));
      r.uv = {phi / (2 * kPi) + 0.5, theta / kPi};
      const double rs = std::sqrt(p.x * p.x + p.z * p.z);
      r.dpdu = Vec3{p.z, 0, -p.x} * (2 * kPi);
      r.dpdv =
          rs > 0 ? Vec3{p.x * p.y / rs, -rs, p.z * p.y / rs} * kPi : Vec3{0, 0, s.radius * kPi};
      break;
    }
    case AnalyticShape::Kind::Plane:
      r.uv = {p.x, p.z};
      r.dpdu = {1, 0, 0};
      r.dpdv = {0, 0, 1};
      break;
    case AnalyticShape::Kind::Disk:
      r.uv = {p.x / (2 * s.radius) + 0.5, p.z / (2 * s.radius) + 0.5};
      r.dpdu = {2 * s.radius, 0, 0};
      r.dpdv = {0, 0, 2 * s.radius};
      break;
    case AnalyticShape::Kind::Rectangle:  // u along edge_u (object z), v along edge_v (x)
      r.uv = {p.z + 0.5, p.x + 0.5};
      r.dpdu = {0, 0, 1};
      r.dpdv = {1, 0, 0};
      break;
    case AnalyticShape::Kind::Box: {
      const int axis = box_axis(s, p);
      const int a = (axis + 1) % 3, b = (axis + 2) % 3;
      r.uv = {p[a] / s.size[a] + 0.5, p[b] / s.size[b] + 0.5};
      r.dpdu = Vec3{};
      r.dpdu[a] = s.size[a];
      r.dpdv = Vec3{};
      r.dpdv[b] = s.size[b];
      break;
    }
    case AnalyticShape::Kind::Cylinder: {
      const double rr = std::sqrt(p.x * p.x + p.z * p.z);
      if (on_cylinder_cap(s, p, rr)) {
        r.uv = {p.x / (2 * s.radius) + 0.5, p.z / (2 * s.radius) + 0.5};
        r.dpdu = {2 * s.radius, 0, 0};
        r.dpdv = {0, 0, 2 * s.radius};
      } else {
        r.uv = {std::atan2(p.x, p.z) / (2 * kPi) + 0.5, p.y / s.height};
        r.dpdu = Vec3{p.z, 0, -p.x} * (2 * kPi);
        r.dpdv = {0, s.height, 0};
      }
      break;
    }
  }
  return r;
}

}  // namespace anamorph
