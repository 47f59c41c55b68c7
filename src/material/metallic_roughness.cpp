// The `metallic_roughness` material kind: its keys, its BSDF and its registry entry.
#include "material/metallic_roughness.h"

#include <algorithm>

#include "material/material_kinds.h"

namespace anamorph {

Bsdf MetallicRoughnessMaterial::bsdf(const ShadingPoint& sp, const Vec3& wo) const {
  Bsdf b = bsdf_frame(sp, wo);
  const Color base = base_color.eval(sp.tex);
  const Color mr = metallic_roughness.eval(sp.tex);
  const double metal = std::clamp(metallic * mr.z, 0.0, 1.0);
  const double rough = std::clamp(roughness * mr.y, 0.0, 1.0);
  b.diffuse = base * ((1 - metal) * (1 - transmission));
  const Color f0 = lerp(metal, dielectric_f0, base);
  const double a = rough * rough;
  if (a < 0.02) {
    b.mirror = f0;  // too sharp for a microfacet lobe: a mirror with the same tint
  } else {
    b.ggx_f0 = f0;
    b.ggx_alpha = a;
  }
  b.transmission = transmission * (1 - metal);
  return b;
}

namespace {

// clang-format off
const ParamSpec kParams[] = {
    {"metallic", ParamType::Number, "0", "glTF metalness.", 0, 1},
    {"roughness", ParamType::Number, "0.5", "glTF roughness (GGX alpha = roughness^2).", 0, 1},
    {"transmission", ParamType::Number, "0",
     "Smooth dielectric (refraction with Fresnel) weight.", 0, 1},
};
// clang-format on

std::unique_ptr<Material> create(const ParamValues& v) {
  auto m = std::make_unique<MetallicRoughnessMaterial>();
  m->metallic = v.number("metallic");
  m->roughness = v.number("roughness");
  m->transmission = v.number("transmission");
  return m;
}

}  // namespace

extern const MaterialKind kMetallicRoughnessKind;  // (in the list of material_kinds.cpp)
const MaterialKind kMetallicRoughnessKind{MetallicRoughnessMaterial::kType,
                                          "glTF 2.0's metallic-roughness model.", kParams, create};

}  // namespace anamorph
