// The BSDF at a shading point, in the local frame of the shading normal (z up). Lobes:
// Lambert diffuse, a normalized Phong lobe (Whitted specular), GGX microfacet reflection
// (glTF metallic-roughness), perfect mirror reflection and a smooth dielectric (both delta).
#pragma once

#include "math/frame.h"
#include "math/vec.h"

namespace anamorph {

struct BsdfSample {
  Vec3 wi;       // world space
  Color f;       // BSDF value times |cos| / pdf already applied? No: raw f (see `weight`)
  Color weight;  // f * |cos theta_i| / pdf
  double pdf = 0;
  bool delta = false;
};

struct Bsdf {
  Frame frame;    // shading frame (n = shading normal, facing the outgoing ray)
  Vec3 ng;        // geometric normal, same side as frame.n
  Color diffuse;  // Lambert albedo
  Color phong;    // Phong specular colour (ks)
  double phong_exponent = 50;
  Color ggx_f0;  // GGX Schlick F0 (0 = no GGX lobe)
  double ggx_alpha = 0.25;
  Color mirror;             // perfect mirror weight
  double transmission = 0;  // smooth dielectric weight
  double eta = 1.5;         // ior inside / outside (the frame faces the outside)
  bool entering = true;     // the ray arrives from the outside

  bool has_delta() const { return max_component(mirror) > 0 || transmission > 0; }
  bool has_smooth() const {
    return max_component(diffuse) > 0 || max_component(phong) > 0 || max_component(ggx_f0) > 0;
  }
  // Non-delta lobes only.
  Color eval(const Vec3& wo, const Vec3& wi) const;
  double pdf(const Vec3& wo, const Vec3& wi) const;
  // Samples all lobes; u3 picks the lobe.
  bool sample(const Vec3& wo, Vec2 u, double u3, BsdfSample* out) const;
};

double fresnel_dielectric(double cos_i, double eta);
Color fresnel_schlick(const Color& f0, double cos_theta);

}  // namespace anamorph
