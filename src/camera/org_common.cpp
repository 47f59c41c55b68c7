#include "camera/org_common.h"

#include <cmath>
#include <limits>

#include "math/simd.h"

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
  // One division, not five: it was most of a spline camera's normal (cross_normal_kernel
  // computes the same, bit for bit).
  const double il = 1 / len;
  const Vec3 n = N * il;
  // d(N/|N|) = (dN - n (n . dN)) / |N|
  out->n = n * s;
  out->dndu = (Ns - n * dot(n, Ns)) * (s * su * il);
  out->dndv = (Nt - n * dot(n, Nt)) * (s * sv * il);
  return true;
}

bool set_cross_normal(const LocalGeom& g, double su, double sv, bool flip, SurfaceSample* out) {
  const Vec3 N = cross(g.ps, g.pt);
  const Vec3 Ns = cross(g.pss, g.pt) + cross(g.ps, g.pst);
  const Vec3 Nt = cross(g.pst, g.pt) + cross(g.ps, g.ptt);
  return set_normal(N, Ns, Nt, su, sv, flip, out);
}

namespace {

[[gnu::always_inline]] inline void cross_normal_kernel(const LocalGeomBatch& __restrict g,
                                                       double su, double sv, double sign,
                                                       double min_ps2, double min_pt2, int n,
                                                       SurfaceBatch* __restrict out,
                                                       bool* __restrict check) {
  constexpr int N = kCameraBatch;
  alignas(64) double m_ps[N], m_pt[N], m_n[N], fin[N];
  // (Lambdas in a kernel need always_inline, see math/simd.h.)
  const auto at = [](const double(&a)[3][N], int i) __attribute__((always_inline)) {
    return Vec3{a[0][i], a[1][i], a[2][i]};
  };
  const auto put = [](double(&a)[3][N], int i, const Vec3& x) __attribute__((always_inline)) {
    a[0][i] = x.x, a[1][i] = x.y, a[2][i] = x.z;
  };
  for (int i = 0; i < n; ++i) {
    const Vec3 ps = at(g.ps, i), pt = at(g.pt, i), pss = at(g.pss, i), pst = at(g.pst, i),
               ptt = at(g.ptt, i);
    // set_position
    put(out->p, i, at(g.p, i));
    put(out->dpdu, i, ps * su);
    put(out->dpdv, i, pt * sv);
    put(out->dpduu, i, pss * (su * su));
    put(out->dpduv, i, pst * (su * sv));
    put(out->dpdvv, i, ptt * (sv * sv));
    // set_cross_normal
    const Vec3 Nv = cross(ps, pt);
    const Vec3 Ns = cross(pss, pt) + cross(ps, pst);
    const Vec3 Nt = cross(pst, pt) + cross(ps, ptt);
    const double ps2 = dot(ps, ps), pt2 = dot(pt, pt), n2 = dot(Nv, Nv);
    const double len = length(Nv);
    // set_normal without its tests: lanes that fail them are flagged below for the caller.
    const double il = 1 / len;
    const Vec3 nn = Nv * il;
    put(out->n, i, nn * sign);
    put(out->dndu, i, (Ns - nn * dot(nn, Ns)) * (sign * su * il));
    put(out->dndv, i, (Nt - nn * dot(nn, Nt)) * (sign * sv * il));
    // (Margins as doubles, compared in a loop of their own: a > b iff a - b > 0, also for
    // subnormals, infinities and NaN.)
    m_ps[i] = ps2 - min_ps2, m_pt[i] = pt2 - min_pt2, m_n[i] = n2 - 1e-18 * ps2 * pt2;
    fin[i] = len * 0;
  }
  for (int i = 0; i < n; ++i)
    check[i] = !((m_ps[i] > 0) & (m_pt[i] > 0) & (m_n[i] > 0) & (fin[i] == 0));
  for (int i = 0; i < n; ++i) out->ok[i] = true;
}

ANAMORPH_KERNEL_BODY void cross_normal_clones_body(const LocalGeomBatch& g, double su, double sv,
                                                   double sign, double min_ps2, double min_pt2,
                                                   int n, SurfaceBatch* out, bool* check) {
  with_trip_count<kCameraBatch>(
      n, [&](auto m) __attribute__((always_inline)) {
        cross_normal_kernel(g, su, sv, sign, min_ps2, min_pt2, m, out, check);
      });
}
constexpr simd::Kernel<cross_normal_clones_body> cross_normal_clones;

}  // namespace

void cross_normal_batch(const LocalGeomBatch& g, double su, double sv, bool flip, double min_ps2,
                        double min_pt2, int n, SurfaceBatch* out, bool* check) {
  cross_normal_clones(g, su, sv, flip ? -1.0 : 1.0, min_ps2, min_pt2, n, out, check);
}

LocalGeom transform_geom(const LocalGeom& g, const Mat3& m, Vec3 origin) {
  return {origin + m * g.p, m * g.ps, m * g.pt, m * g.pss, m * g.pst, m * g.ptt};
}

}  // namespace anamorph

namespace anamorph {

void OrgFunction::eval_batch(const double* u, const double* v, int n, SurfaceBatch* out) const {
  org_batch_by_eval(*this, u, v, n, out);
}

void DirFunction::eval_batch(const double* u, const double* v, int n, const SurfaceBatch& org,
                             DirBatch* out) const {
  dir_batch_by_eval(*this, u, v, n, org, out);
}

}  // namespace anamorph
