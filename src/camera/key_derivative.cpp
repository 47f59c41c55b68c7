// VirtualCamera::key_derivative: d(org, dir)/d(key) of a camera's ray at a fixed image position,
// exact, for the camera solver (docs/solve.md "How it solves"). The world ray is
//
//   rig(k) * deform(plain(uv; k), sites(k), coin keys(k))
//
// and each factor is differentiated along the key: the preset's camera-space ray and its rig by
// the preset's closed forms (PresetDerivatives), the coins' deformation (coins.h) by forward-mode
// dual numbers, and the coins' sites, where the camera without coins sees them, by the implicit
// function theorem (the coin stays on the plain ray at its site: as in solve/goals.cpp).
#include <array>
#include <cmath>
#include <vector>

#include "camera/virtual_camera.h"
#include "math/dual.h"

namespace anamorph {

namespace {

// A coin's site with the derivatives of its numbers along the key.
struct DualSite {
  Dual u, v, lc, m, radius, stiffness;
  DVec3 pc;
  CoinAffects affects = CoinAffects::Both;
  CoinFalloff falloff = CoinFalloff::Smooth;
};

DualSite constant_site(const CoinSite& s) {
  return {s.uv.x,      s.uv.y,           s.lc,      s.strength, s.radius,
          s.stiffness, dual(s.p_camera), s.affects, s.falloff};
}

// The deformation of CoinField::apply (coins.h: p + sum w e, normalize(d + sum w (e / |e| - d)),
// w = m B_s(K(x)) A(z)) on dual numbers; the direction is returned unit.
void deform(const std::vector<DualSite>& sites, Vec2 uv, DVec3* org, DVec3* dir) {
  const DVec3 p = *org, d0 = *dir;
  DVec3 po = p, d = d0;
  for (const DualSite& c : sites) {
    const Dual qu = Dual(uv.x) - c.u, qv = Dual(uv.y) - c.v;
    const Dual x = (qu * qu + qv * qv) / (c.radius * c.radius);
    if (!(x.v < 1)) continue;
    const KernelValue kv = coin_kernel(c.falloff, x.v);
    const Dual y{kv.k, kv.dk * x.d};
    const Dual b = c.stiffness * y / (Dual(1) + (c.stiffness - Dual(1)) * y);
    const DVec3 e = c.pc - p;
    const Dual ee = dot(e, e), z = ee / (c.lc * c.lc);
    const Dual w = c.m * b * (Dual(2) * z / (Dual(1) + z * z));
    if (int(c.affects) & int(CoinAffects::Org)) po += e * w;
    if ((int(c.affects) & int(CoinAffects::Dir)) && ee.v > 0) d += (e / sqrt(ee) - d0) * w;
  }
  *org = po;
  *dir = dual_normalize(d);
}

}  // namespace

// How a site moves when the key moves the coin by `dpc` (camera space) and the plain rays at fixed
// (u, v) by the preset's ray derivative (`ray_key`, empty: they do not move): its (uc, vc) by the
// implicit function theorem on F = (pc - org(uc)) x dir(uc) = 0, its lc = |pc - org(uc)| along.
static bool move_site(const VirtualCamera& cam, const CoinSite& s, const Vec3& dpc,
                      const std::string* ray_key, const PresetDerivatives::RayFn& preset_ray,
                      DualSite* out) {
  const std::optional<CameraRay> r = cam.generate_uncoined(s.uv);
  if (!r) return false;
  Vec3 dp{}, dd{};
  if (ray_key && !preset_ray(*ray_key, *r, &dp, &dd)) return false;
  const Vec3 q = s.p_camera - r->org;
  const Vec3 fu = cross(-r->dorg_du, r->dir) + cross(q, r->ddir_du);
  const Vec3 fv = cross(-r->dorg_dv, r->dir) + cross(q, r->ddir_dv);
  const Vec3 fk = cross(dpc - dp, r->dir) + cross(q, dd);
  const double a = dot(fu, fu), b = dot(fu, fv), c = dot(fv, fv), det = a * c - b * b;
  if (!(det > 1e-24 * a * c) || !std::isfinite(det)) return false;
  const double gu = -dot(fu, fk), gv = -dot(fv, fk);
  const Vec2 duv{(c * gu - b * gv) / det, (a * gv - b * gu) / det};
  const Vec3 dorg = r->dorg_du * duv.x + r->dorg_dv * duv.y + dp;
  out->u.d = duv.x, out->v.d = duv.y;
  out->lc.d = dot(q, dpc - dorg) / s.lc;
  out->pc = dual(s.p_camera, dpc);
  return true;
}

bool VirtualCamera::key_derivative(const CameraKey& key, Vec2 uv, Vec3* dorg, Vec3* ddir) const {
  const Mat4& m = world_from_camera_.matrix();
  if (moving_ || dof_.aperture_radius > 0 || !(m.m[3] == std::array<double, 4>{0, 0, 0, 1}))
    return false;
  const std::optional<CameraRay> r = generate_uncoined(uv);
  if (!r) return false;
  // The key's own effect: on the plain camera-space rays (preset), the rig (pose) or a coin.
  Vec3 dp{}, dd{};
  Mat4 g{};
  bool ray_key = false, pose = false;
  if (key.coin < 0) {
    ray_key = derivatives_.ray && derivatives_.ray(key.name, *r, &dp, &dd);
    pose = !ray_key && derivatives_.rig && derivatives_.rig(key.name, key.component, &g);
    if (!ray_key && !pose) return false;
  } else if ((key.name != "strength" && key.name != "radius" && key.name != "stiffness" &&
              key.name != "position") ||
             key.component < 0 || key.component > 2) {
    return false;
  }
  const auto by_g = [&g](const Vec3& x, double w) {  // G (x, w): w = 1 a point, 0 a vector
    Vec3 y;
    for (int i = 0; i < 3; ++i)
      y[i] = g.m[i][0] * x.x + g.m[i][1] * x.y + g.m[i][2] * x.z + g.m[i][3] * w;
    return y;
  };
  std::vector<DualSite> sites;
  bool found = false;
  for (const CoinSite& s : coins_.sites()) {
    DualSite d = constant_site(s);
    const bool own = s.coin == key.coin;
    found = found || own;
    if (own && key.name == "strength") d.m.d = 1;
    if (own && key.name == "radius") d.radius.d = 1;
    if (own && key.name == "stiffness") d.stiffness.d = 1;
    const bool moves = (own && key.name == "position") || key.coin < 0;
    Vec3 e{};
    if (own && key.name == "position") e[key.component] = 1;
    const Vec3 dpc = own    ? world_from_camera_.inverse().vector(e)
                     : pose ? -by_g(s.p_camera, 1)
                            : Vec3{};
    if (moves && !move_site(*this, s, dpc, ray_key ? &key.name : nullptr, derivatives_.ray, &d))
      return false;
    sites.push_back(d);
  }
  // A strength-0 coin is dropped (no site), yet its strength's derivative is not zero.
  if (key.coin >= 0 && !found && key.name == "strength") return false;
  DVec3 o = dual(r->org, dp), di = dual(r->dir, dd);
  deform(sites, uv, &o, &di);
  if (pose) {  // world = rig (1 + G dk) camera
    o = dual(dual_value(o), dual_derivative(o) + by_g(dual_value(o), 1));
    di = dual(dual_value(di), dual_derivative(di) + by_g(dual_value(di), 0));
  }
  DVec3 ow, dw;
  for (int i = 0; i < 3; ++i) {
    ow[i] = Dual(m.m[i][3]);
    for (int j = 0; j < 3; ++j) ow[i] += Dual(m.m[i][j]) * o[j], dw[i] += Dual(m.m[i][j]) * di[j];
  }
  *dorg = dual_derivative(ow);
  *ddir = dual_derivative(dual_normalize(dw));
  return true;
}

}  // namespace anamorph
