// `metallic_roughness`: glTF 2.0's core material. A base colour that is diffuse for dielectrics
// and the specular tint of metals, GGX microfacet reflection with Schlick's Fresnel (a mirror of
// the same tint when too smooth for a microfacet lobe), and a smooth dielectric for transmission
// (KHR_materials_transmission): the refracted light tinted by the base colour, a refracting solid
// absorbing inside (KHR_materials_volume) or a thin wall (no volume). Its reflection is the
// dielectric's Fresnel: the F0 mirror is kept for the opaque share, 1 - transmission.
// Over it, two layers (bsdf.h, layers.cpp): a clear coat (KHR_materials_clearcoat: a GGX
// dielectric of IOR 1.5 with its own roughness and normal) and a sheen (KHR_materials_sheen:
// Charlie's distribution), each taking from the base what it reflects.
// The member defaults are glTF's (metallic and roughness 1); a scene file's are in its keys.
#pragma once

#include "material/material.h"

namespace anamorph {

class MetallicRoughnessMaterial final : public Material {
 public:
  static constexpr std::string_view kType = "metallic_roughness";

  double metallic = 1, roughness = 1;
  // A dielectric's reflectance at normal incidence (KHR_materials_specular):
  // min(specular_color x colour texture's RGB, 1) x specular x the specular texture's alpha, with
  // specular_color = F0(ior) x specularColorFactor; 0.04 without the extension.
  Color specular_color{0.04, 0.04, 0.04};
  double specular = 1;
  Texture specular_texture = Texture::constant({1, 1, 1});        // its alpha
  Texture specular_color_texture = Texture::constant({1, 1, 1});  // sRGB RGB
  Texture metallic_roughness = Texture::constant({1, 1, 1});      // G = roughness, B = metallic
  double transmission = 0;  // smooth dielectric weight, x the texture's R
  Texture transmission_texture = Texture::constant({1, 1, 1});
  bool thin = false;  // transmission through a thin wall (no refraction)
  // KHR_materials_volume's thickness factor (> 0 unless thin) x this texture's G: a point where
  // it is 0 is a thin wall (the thickness itself is the geometry's: rays cross the real solid).
  Texture thickness_texture = Texture::constant({1, 1, 1});
  Color absorption{0, 0, 0};  // inside the solid, per unit length (glTF: -ln(c) / distance)
  // Clear coat: weight x texture's R, roughness x texture's G; its own normal map (none: the
  // surface's interpolated normal, not the base's normal map).
  double clearcoat = 0, clearcoat_roughness = 0;
  Texture clearcoat_texture = Texture::constant({1, 1, 1});
  Texture clearcoat_roughness_texture = Texture::constant({1, 1, 1});
  Texture clearcoat_normal;
  bool has_clearcoat_normal = false;
  double clearcoat_normal_scale = 1;
  // Sheen: colour x texture (sRGB RGB), roughness x texture's alpha.
  Color sheen_color{0, 0, 0};
  double sheen_roughness = 0;
  Texture sheen_color_texture = Texture::constant({1, 1, 1});
  Texture sheen_roughness_texture = Texture::constant({1, 1, 1});

  std::string_view type() const override { return kType; }
  Bsdf bsdf(const ShadingPoint& sp, const Vec3& wo) const override;
  Color diffuse_reflectance() const override { return base_color.value * (1 - metallic); }
  double shadow_transmission() const override { return transmission; }
  // (Smooth spots are mirrors: rays may go on from any hit.)
  bool spawns_specular_rays() const override { return true; }
  bool textured() const override {
    const auto image = [](const Texture& t) { return t.kind != Texture::Kind::Constant; };
    return Material::textured() || image(metallic_roughness) || image(clearcoat_texture) ||
           image(clearcoat_roughness_texture) || has_clearcoat_normal ||
           image(sheen_color_texture) || image(sheen_roughness_texture) ||
           image(specular_texture) || image(specular_color_texture) ||
           image(transmission_texture) || image(thickness_texture);
  }
  std::string describe() const override;
  // The dielectric's F0 at sp (KHR_materials_specular, above).
  Color dielectric_f0(const ShadingPoint& sp) const;

 private:
  void add_layers(const ShadingPoint& sp, const Vec3& wo, Bsdf* b) const;
};

}  // namespace anamorph
