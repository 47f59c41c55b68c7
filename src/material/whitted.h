// `whitted`: the paper's model. A diffuse colour, a normalized Phong highlight, a perfect mirror
// and a smooth dielectric (refraction with Fresnel), each with its weight.
#pragma once

#include "material/material.h"

namespace anamorph {

class WhittedMaterial final : public Material {
 public:
  static constexpr std::string_view kType = "whitted";

  double diffuse = 1;       // kd multiplier of base_color
  Color specular{0, 0, 0};  // Phong highlight colour (ks)
  double exponent = 50;     // Phong exponent
  double reflectivity = 0;  // mirror reflection weight
  double transmission = 0;  // refraction weight

  std::string_view type() const override { return kType; }
  Bsdf bsdf(const ShadingPoint& sp, const Vec3& wo) const override;
  Color diffuse_reflectance() const override { return base_color.value * diffuse; }
  double shadow_transmission() const override { return transmission; }
  bool spawns_specular_rays() const override { return transmission > 0 || reflectivity > 0; }
};

}  // namespace anamorph
