#include "material/material.h"

#include <algorithm>
#include <cmath>

#include "math/frame.h"

namespace anamorph {

Vec3 Material::mapped_normal(const Texture& map, double scale, const ShadingPoint& sp, Vec3 ns) {
  const Color t = map.eval(sp.tex);
  const Vec3 tn{(2 * t.x - 1) * scale, (2 * t.y - 1) * scale, 2 * t.z - 1};
  Vec3 tangent = sp.dpdu - ns * dot(ns, sp.dpdu);
  if (length(tangent) > 1e-12) {
    tangent = normalize(tangent);
    Vec3 bitangent = cross(ns, tangent);
    // glTF normal maps: +y points toward decreasing v (uv origin at the top left).
    if (dot(bitangent, sp.dpdv) > 0) bitangent = -bitangent;
    const Vec3 mapped = tangent * tn.x + bitangent * tn.y + ns * tn.z;
    if (length(mapped) > 0) ns = normalize(mapped);
  }
  return ns;
}

Bsdf Material::bsdf_frame(const ShadingPoint& sp, const Vec3& wo) const {
  Bsdf b;
  const bool front = dot(wo, sp.ng) >= 0;
  Vec3 ng = front ? sp.ng : -sp.ng;
  Vec3 ns = front ? sp.ns : -sp.ns;
  if (has_normal_map) ns = mapped_normal(normal_map, normal_scale, sp, ns);
  // Keep the shading normal on the viewer's side so lobes are not lost.
  if (dot(ns, wo) <= 0) ns = normalize(ns - wo * (dot(ns, wo) - 1e-4));
  b.frame = Frame::from_normal(ns);
  b.ng = ng;
  b.entering = front;
  b.eta = ior;
  if (blends()) b.opacity = opacity_at(sp.tex);
  return b;
}

double Material::opacity_at(const TexCoord& tc) const {
  double alpha = 1;
  base_color.eval(tc, &alpha);
  return std::clamp(alpha, 0.0, 1.0);
}

}  // namespace anamorph
