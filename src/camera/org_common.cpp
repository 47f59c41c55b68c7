#include "camera/org_common.h"

#include <cmath>
#include <limits>

namespace anamorph {

AxisFrame read_axis_frame(const ParamValues& v, std::string_view axis_key,
                          std::string_view front_key) {
  const Vec3 axis = v.vec3(axis_key);
  if (!(length(axis) > 0))
    throw ParamError(std::string(axis_key), std::string(axis_key) + " must not be zero");
  AxisFrame f;
  f.up = normalize(axis);
  const auto project = [&](Vec3 d) { return d - f.up * dot(f.up, d); };
  Vec3 front;
  if (v.has(front_key)) {
    const Vec3 given = v.vec3(front_key);
    front = project(given);
    if (!(length(front) > 1e-9 * length(given)))
      throw ParamError(
          std::string(front_key),
          std::string(front_key) + " must not be zero or parallel to " + std::string(axis_key));
  } else {
    front = project({0, 0, -1});
    // Along z there is no projection of -z: take the direction a rotation of +y onto the axis
    // would carry -z to.
    if (!(length(front) > 1e-6)) front = {0, f.up.z > 0 ? 1.0 : -1.0, 0};
  }
  f.back = -normalize(front);
  f.right = cross(f.up, f.back);
  return f;
}

ParamRange read_range(const ParamValues& v, std::string_view key) {
  const Vec2 r = v.vec2(key);
  if (r.x == r.y)
    throw ParamError(std::string(key), std::string(key) + " must not be empty (both ends equal)");
  return {r.x, r.y};
}

ParamRange read_angle_range(const ParamValues& v, std::string_view key) {
  const ParamRange r = read_range(v, key);
  return {radians(r.a), radians(r.b)};
}

void set_position(const LocalGeom& g, double su, double sv, SurfaceSample* out) {
  out->p = g.p;
  out->dpdu = g.ps * su;
  out->dpdv = g.pt * sv;
  out->dpduu = g.pss * (su * su);
  out->dpduv = g.pst * (su * sv);
  out->dpdvv = g.ptt * (sv * sv);
}

bool set_normal(Vec3 N, Vec3 Ns, Vec3 Nt, double su, double sv, bool flip, SurfaceSample* out) {
  const double len = length(N);
  if (!(len > 0) || !std::isfinite(len)) {
    out->n = out->dndu = out->dndv = Vec3{};
    return false;
  }
  const double s = flip ? -1.0 : 1.0;
  const Vec3 n = N / len;
  // d(N/|N|) = (dN - n (n . dN)) / |N|
  out->n = n * s;
  out->dndu = (Ns - n * dot(n, Ns)) * (s * su / len);
  out->dndv = (Nt - n * dot(n, Nt)) * (s * sv / len);
  return true;
}

bool set_cross_normal(const LocalGeom& g, double su, double sv, bool flip, SurfaceSample* out) {
  const Vec3 N = cross(g.ps, g.pt);
  const Vec3 Ns = cross(g.pss, g.pt) + cross(g.ps, g.pst);
  const Vec3 Nt = cross(g.pst, g.pt) + cross(g.ps, g.ptt);
  return set_normal(N, Ns, Nt, su, sv, flip, out);
}

LocalGeom transform_geom(const LocalGeom& g, const Mat3& m, Vec3 origin) {
  return {origin + m * g.p, m * g.ps, m * g.pt, m * g.pss, m * g.pst, m * g.ptt};
}

}  // namespace anamorph

namespace anamorph {

void OrgFunction::eval_grid(std::span<const double> us, std::span<const double> vs,
                            SurfaceSample* out) const {
  for (size_t j = 0; j < vs.size(); ++j)
    for (size_t i = 0; i < us.size(); ++i) {
      SurfaceSample& s = out[j * us.size() + i];
      if (!eval({us[i], vs[j]}, &s)) s.p = Vec3(std::numeric_limits<double>::quiet_NaN());
    }
}

void OrgFunction::eval_batch(const double* u, const double* v, int n, SurfaceSample* out,
                             bool* ok) const {
  org_batch_by_eval(*this, u, v, n, out, ok);
}

void DirFunction::eval_batch(const double* u, const double* v, int n, const SurfaceSample* org,
                             int org_stride, DirBatch* out) const {
  dir_batch_by_eval(*this, u, v, n, org, org_stride, out);
}

}  // namespace anamorph
