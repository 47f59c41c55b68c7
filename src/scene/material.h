// Materials. One struct serves both models so loaders and the parser fill the same thing:
// `Whitted` is the paper's classic model; `MetallicRoughness` is glTF 2.0's (GGX microfacet).
#pragma once

#include <string>

#include "scene/texture.h"

namespace anamorph {

struct Material {
  enum class Model { Whitted, MetallicRoughness };
  std::string name;
  Model model = Model::Whitted;

  // Shared
  Texture base_color = Texture::constant({0.8, 0.8, 0.8});  // diffuse colour / glTF baseColor
  Texture emission = Texture::constant({0, 0, 0});  // radiance emitted (x emission_strength)
  double emission_strength = 1;

  // Whitted
  double diffuse = 1;       // kd multiplier of base_color
  Color specular{0, 0, 0};  // Phong highlight colour (ks)
  double exponent = 50;     // Phong exponent
  double reflectivity = 0;  // mirror reflection weight
  double transmission = 0;  // refraction weight
  double ior = 1.5;         // index of refraction (also used for Fresnel)

  // glTF metallic-roughness
  double metallic = 1, roughness = 1;
  // A dielectric's reflectance at normal incidence (KHR_materials_specular: F0(ior) x
  // specularColorFactor, at most 1, x specularFactor; 0.04 without the extension).
  Color dielectric_f0{0.04, 0.04, 0.04};
  Texture metallic_roughness = Texture::constant({1, 1, 1});  // G = roughness, B = metallic
  Texture normal_map;  // tangent-space normal map (Kind::Constant = none)
  bool has_normal_map = false;
  double normal_scale = 1;
  enum class AlphaMode { Opaque, Mask, Blend };
  AlphaMode alpha_mode = AlphaMode::Opaque;
  double alpha_cutoff = 0.5;
  bool double_sided = true;

  // Some texture is not a constant: shading reads texture coordinates (and their footprint).
  bool textured() const {
    return base_color.kind != Texture::Kind::Constant || has_normal_map ||
           metallic_roughness.kind != Texture::Kind::Constant ||
           emission.kind != Texture::Kind::Constant;
  }
  bool is_emissive() const {
    return emission.kind != Texture::Kind::Constant || max_component(emission.value) > 0;
  }
};

}  // namespace anamorph
