#include "render/shading.h"

#include "math/frame.h"

#include <algorithm>
#include <cmath>

namespace anamorph {

Footprint footprint_at(const CameraRay& r, double du, double dv, const Hit& h) {
  // Intersect the offset rays with the tangent plane at the hit (pbrt's method).
  Footprint fp;
  const Vec3 n = h.ng;
  const double d = dot(n, h.p);
  auto offset_hit = [&](const Vec3& o, const Vec3& dir) -> Vec3 {
    const double den = dot(n, dir);
    if (std::abs(den) < 1e-12) return h.p;
    const double t = (d - dot(n, o)) / den;
    return o + dir * t;
  };
  // (The offset rays' directions need no normalizing: where a line meets a plane does not
  // depend on its direction's length. Square roots and divisions were a tenth of a textured
  // Whitted render.)
  fp.dpdx = offset_hit(r.org + r.dorg_du * du, r.dir + r.ddir_du * du) - h.p;
  fp.dpdy = offset_hit(r.org + r.dorg_dv * dv, r.dir + r.ddir_dv * dv) - h.p;
  if (!is_finite(fp.dpdx) || !is_finite(fp.dpdy)) fp = {};
  // The angular spread of the pixel's rays, and how their origins fan out, both per unit of
  // distance at the hit, continue the footprint along secondary rays.
  fp.spread = std::sqrt(
      std::max(dot(r.ddir_du, r.ddir_du) * (du * du), dot(r.ddir_dv, r.ddir_dv) * (dv * dv)));
  return fp;
}

Footprint propagate(const Footprint& fp, const Hit& next) {
  Footprint out;
  out.spread = fp.spread;
  const double width = 0.5 * (length(fp.dpdx) + length(fp.dpdy)) + next.t * fp.spread;
  if (!(width > 0) || !std::isfinite(width)) return out;
  const Frame f = Frame::from_normal(next.ng);
  out.dpdx = f.s * width;
  out.dpdy = f.t * width;
  return out;
}

TexCoord texcoord_at(const Hit& h, const Footprint& fp) {
  TexCoord tc;
  tc.uv = h.uv;
  tc.p_world = h.p;
  tc.p_object = h.p_object;
  tc.n_world = h.ng;
  tc.n_object = h.n_object;
  tc.object_from_world = h.object_from_world;
  tc.dpdx = fp.dpdx;
  tc.dpdy = fp.dpdy;
  // Least squares: dp = dpdu du + dpdv dv.
  const double a = dot(h.dpdu, h.dpdu), b = dot(h.dpdu, h.dpdv), c = dot(h.dpdv, h.dpdv);
  const double det = a * c - b * b;
  if (std::abs(det) > 1e-30) {
    auto solve = [&](const Vec3& dp) {
      const double ru = dot(h.dpdu, dp), rv = dot(h.dpdv, dp);
      return Vec2{(c * ru - b * rv) / det, (a * rv - b * ru) / det};
    };
    tc.duvdx = solve(fp.dpdx);
    tc.duvdy = solve(fp.dpdy);
  }
  return tc;
}

Bsdf make_bsdf(const Material& m, const Hit& h, const Vec3& wo, const TexCoord& tc, Color* albedo) {
  Bsdf b;
  const bool front = dot(wo, h.ng) >= 0;
  Vec3 ng = front ? h.ng : -h.ng;
  Vec3 ns = front ? h.ns : -h.ns;
  if (m.has_normal_map) {
    const Color t = m.normal_map.eval(tc);
    const Vec3 tn{(2 * t.x - 1) * m.normal_scale, (2 * t.y - 1) * m.normal_scale, 2 * t.z - 1};
    Vec3 tangent = h.dpdu - ns * dot(ns, h.dpdu);
    if (length(tangent) > 1e-12) {
      tangent = normalize(tangent);
      Vec3 bitangent = cross(ns, tangent);
      // glTF normal maps: +y points toward decreasing v (uv origin at the top left).
      if (dot(bitangent, h.dpdv) > 0) bitangent = -bitangent;
      const Vec3 mapped = tangent * tn.x + bitangent * tn.y + ns * tn.z;
      if (length(mapped) > 0) ns = normalize(mapped);
    }
  }
  // Keep the shading normal on the viewer's side so lobes are not lost.
  if (dot(ns, wo) <= 0) ns = normalize(ns - wo * (dot(ns, wo) - 1e-4));
  b.frame = Frame::from_normal(ns);
  b.ng = ng;
  b.entering = front;
  b.eta = m.ior;

  double alpha;
  const Color base = m.base_color.eval(tc, &alpha);
  if (albedo) *albedo = base;
  if (m.model == Material::Model::Whitted) {
    b.diffuse = base * (m.diffuse * std::max(0.0, 1 - m.reflectivity - m.transmission));
    b.phong = m.specular;
    b.phong_exponent = m.exponent;
    b.mirror = Color(m.reflectivity);
    b.transmission = m.transmission;
  } else {
    const Color mr = m.metallic_roughness.eval(tc);
    const double metallic = std::clamp(m.metallic * mr.z, 0.0, 1.0);
    const double rough = std::clamp(m.roughness * mr.y, 0.0, 1.0);
    b.diffuse = base * ((1 - metallic) * (1 - m.transmission));
    const Color f0 = lerp(metallic, m.dielectric_f0, base);
    const double a = rough * rough;
    if (a < 0.02) {
      b.mirror = f0;  // too sharp for a microfacet lobe: a mirror with the same tint
    } else {
      b.ggx_f0 = f0;
      b.ggx_alpha = a;
    }
    b.transmission = m.transmission * (1 - metallic);
  }
  return b;
}

}  // namespace anamorph
