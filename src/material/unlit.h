// `unlit`: a surface that reflects and transmits nothing and shows only its emission
// (KHR_materials_unlit: the glTF reader makes the base colour, factor x texture, its emission).
// It is an emitter like any other: in the path tracer it also lights what it faces.
#pragma once

#include "material/material.h"

namespace anamorph {

class UnlitMaterial final : public Material {
 public:
  static constexpr std::string_view kType = "unlit";

  std::string_view type() const override { return kType; }
  Bsdf bsdf(const ShadingPoint& sp, const Vec3& wo) const override { return bsdf_frame(sp, wo); }
  Color diffuse_reflectance() const override { return {0, 0, 0}; }
  double shadow_transmission() const override { return 0; }
  bool spawns_specular_rays() const override { return false; }
};

}  // namespace anamorph
