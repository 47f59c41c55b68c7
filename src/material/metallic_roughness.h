// `metallic_roughness`: glTF 2.0's core material. A base colour that is diffuse for dielectrics
// and the specular tint of metals, GGX microfacet reflection with Schlick's Fresnel (a mirror of
// the same tint when too smooth for a microfacet lobe), and a smooth dielectric for transmission
// (KHR_materials_transmission): the refracted light tinted by the base colour, a refracting solid
// absorbing inside (KHR_materials_volume) or a thin wall (no volume). Its reflection is the
// dielectric's Fresnel: the F0 mirror is kept for the opaque share, 1 - transmission.
// The member defaults are glTF's (metallic and roughness 1); a scene file's are in its keys.
#pragma once

#include "material/material.h"

namespace anamorph {

class MetallicRoughnessMaterial final : public Material {
 public:
  static constexpr std::string_view kType = "metallic_roughness";

  double metallic = 1, roughness = 1;
  // A dielectric's reflectance at normal incidence (KHR_materials_specular: F0(ior) x
  // specularColorFactor, at most 1, x specularFactor; 0.04 without the extension).
  Color dielectric_f0{0.04, 0.04, 0.04};
  Texture metallic_roughness = Texture::constant({1, 1, 1});  // G = roughness, B = metallic
  double transmission = 0;                                    // smooth dielectric weight
  bool thin = false;          // transmission through a thin wall (no refraction)
  Color absorption{0, 0, 0};  // inside the solid, per unit length (glTF: -ln(c) / distance)

  std::string_view type() const override { return kType; }
  Bsdf bsdf(const ShadingPoint& sp, const Vec3& wo) const override;
  Color diffuse_reflectance() const override { return base_color.value * (1 - metallic); }
  double shadow_transmission() const override { return transmission; }
  // (Smooth spots are mirrors: rays may go on from any hit.)
  bool spawns_specular_rays() const override { return true; }
  bool textured() const override {
    return Material::textured() || metallic_roughness.kind != Texture::Kind::Constant;
  }
};

}  // namespace anamorph
