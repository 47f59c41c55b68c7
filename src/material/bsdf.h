// The BSDF at a shading point, in the local frame of the shading normal (z up). Lobes:
// Lambert diffuse, a normalized Phong lobe (Whitted specular), GGX microfacet reflection
// (glTF metallic-roughness), perfect mirror reflection and a smooth dielectric (both delta): a
// refracting solid, or a thin wall that light crosses without turning (glTF's transmission
// without a volume); and, for alpha blend, a share of the light passing straight on. Over them
// two layers (layers.cpp, glTF's KHR_materials_clearcoat and KHR_materials_sheen): a clear coat
// and a sheen, each taking from what lies below the light it reflects.
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
  bool pass_through = false;  // alpha blend's share going straight on (wi = -wo)
  double eta_scale = 1;       // eta^2 of a refraction (weight holds 1/eta^2), else 1
};

struct Bsdf {
  Frame frame;    // shading frame (n = shading normal, facing the outgoing ray)
  Vec3 ng;        // geometric normal, same side as frame.n
  Color diffuse;  // Lambert albedo
  Color phong;    // Phong specular colour (ks)
  double phong_exponent = 50;
  Color ggx_f0;  // GGX Schlick F0 (0 = no GGX lobe)
  double ggx_alpha = 0.25;
  Color mirror;                      // perfect mirror weight
  double transmission = 0;           // smooth dielectric weight
  Color transmission_tint{1, 1, 1};  // the refracted light's colour (glTF: the base colour)
  bool thin = false;                 // thin-walled: transmitted rays go on unrefracted
  // Absorption inside the surface's solid, per unit length: the path tracer attenuates the part
  // of a path inside (between entering and leaving) by exp(-sigma_a * length).
  Color sigma_a{0, 0, 0};
  double eta = 1.5;      // ior inside / outside (the frame faces the outside)
  bool entering = true;  // the ray arrives from the outside
  // Alpha blend: the other lobes are scaled by opacity, 1 - opacity goes straight through.
  double opacity = 1;
  // Clear coat: a GGX dielectric layer (F0 = 0.04, IOR 1.5) of weight `coat` in its own frame
  // (its own normal); everything below is scaled by 1 - coat x F(n_coat . wo).
  double coat = 0;
  double coat_alpha = 0.01;
  Frame coat_frame;
  // Sheen: Charlie's distribution (Estevez & Kulla 2017) with Neubelt & Pettineo's visibility,
  // colour `sheen`, alpha = sheen_roughness^2; what lies below is scaled by
  // min(1 - max(sheen) E(wo), 1 - max(sheen) E(wi)), E the sheen's directional albedo.
  Color sheen{0, 0, 0};
  double sheen_roughness = 0.5;

  bool has_delta() const { return max_component(mirror) > 0 || transmission > 0 || opacity < 1; }
  bool has_layers() const { return coat > 0 || max_component(sheen) > 0; }
  bool has_smooth() const {
    return max_component(diffuse) > 0 || max_component(phong) > 0 || max_component(ggx_f0) > 0 ||
           has_layers();
  }
  // Non-delta lobes only.
  Color eval(const Vec3& wo, const Vec3& wi) const;
  double pdf(const Vec3& wo, const Vec3& wi) const;
  // Samples all lobes; u3 picks the lobe.
  bool sample(const Vec3& wo, Vec2 u, double u3, BsdfSample* out) const;

  // ---- The layers (layers.cpp) ----
  // f of the layers over `below` (the other lobes' f), directions local to `frame`.
  Color layered(const Vec3& wo_w, const Vec3& wi_w, const Color& below) const;
  // The share of light the layers leave to a delta lobe below them (wo and wi mirror-like).
  double under_layers(const Vec3& wo_w) const;
  // The layers' lobe-choice weights for sampling, and their share of the pdf (unnormalized).
  double coat_choice(const Vec3& wo_w) const;
  double sheen_choice() const;
  double layers_pdf(const Vec3& wo_w, const Vec3& wi_w, double w_coat, double w_sheen) const;
  // A direction from the coat's GGX (false: below the coat's horizon).
  bool sample_coat(const Vec3& wo_w, Vec2 u, Vec3* wi_w) const;
};

// The sheen lobe's directional albedo E(cos theta, sheen roughness), from a table computed once.
double sheen_albedo(double cos_theta, double roughness);
// GGX (Trowbridge-Reitz) normal distribution and Smith's G1, alpha = roughness^2.
double ggx_d(double cos_h, double alpha);
double smith_g1(double cos_v, double alpha);
// Sampling GGX reflection by its distribution of visible normals (Heitz 2018; the spherical-cap
// form of Dupuy and Benyoub 2023): the mirror of wo about a normal drawn in proportion to
// G1(wo) max(0, wo.h) D(h) / wo.z, in the local frame (z up, wo.z > 0); below the horizon when
// that normal faces away. The weight f cos / pdf of a sample is then F G1(wi) <= F.
Vec3 sample_ggx_visible(const Vec3& wo, double alpha, Vec2 u);
// Its density over wi (both above the surface): G1(wo) D(h) / (4 wo.z).
double ggx_visible_pdf(const Vec3& wo, const Vec3& wi, double alpha);

double fresnel_dielectric(double cos_i, double eta);
Color fresnel_schlick(const Color& f0, double cos_theta);

}  // namespace anamorph
