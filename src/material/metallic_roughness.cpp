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
  b.transmission = transmission * (1 - metal);
  if (a < 0.02) {
    // Too sharp for a microfacet lobe: a mirror with the same tint (for the opaque share only: the
    // transmitting share reflects by the dielectric's own Fresnel).
    b.mirror = b.transmission > 0 ? f0 * (1 - b.transmission) : f0;
  } else {
    b.ggx_f0 = f0;
    b.ggx_alpha = a;
  }
  if (b.transmission > 0) {
    b.transmission_tint = base;
    b.thin = thin;
    b.sigma_a = absorption;
  }
  return b;
}

namespace {

// clang-format off
const ParamSpec kParams[] = {
    {"metallic", ParamType::Number, "0", "glTF metalness.", 0, 1},
    {"roughness", ParamType::Number, "0.5", "glTF roughness (GGX alpha = roughness^2).", 0, 1},
    {"transmission", ParamType::Number, "0",
     "Smooth dielectric (refraction with Fresnel) weight (KHR_materials_transmission); the "
     "refracted light is tinted by `color`.", 0, 1},
    {"thin", ParamType::Bool, "false",
     "Transmission through a thin wall: light goes on unrefracted (glTF transmission without "
     "KHR_materials_volume); false: a refracting solid."},
    {"absorption", ParamType::Color, "0",
     "Absorption inside the solid (path tracer), per unit length per channel: "
     "KHR_materials_volume's -ln(attenuationColor) / attenuationDistance.", 0, kInf, {}, false,
     false, "per scene unit"},
};
// clang-format on

std::unique_ptr<Material> create(const ParamValues& v) {
  auto m = std::make_unique<MetallicRoughnessMaterial>();
  m->metallic = v.number("metallic");
  m->roughness = v.number("roughness");
  m->transmission = v.number("transmission");
  m->thin = v.boolean("thin");
  m->absorption = v.color("absorption");
  return m;
}

}  // namespace

extern const MaterialKind kMetallicRoughnessKind;  // (in the list of material_kinds.cpp)
const MaterialKind kMetallicRoughnessKind{MetallicRoughnessMaterial::kType,
                                          "glTF 2.0's metallic-roughness model.", kParams, create};

}  // namespace anamorph
