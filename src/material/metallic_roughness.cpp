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
  const double trans = transmission * std::clamp(transmission_texture.eval(sp.tex).x, 0.0, 1.0);
  b.diffuse = base * ((1 - metal) * (1 - trans));
  const Color f0 = lerp(metal, dielectric_f0(sp), base);
  const double a = rough * rough;
  b.transmission = trans * (1 - metal);
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
    b.thin = thin || !(thickness_texture.eval(sp.tex).y > 0);
    b.sigma_a = absorption;
  }
  if (clearcoat > 0 || max_component(sheen_color) > 0) add_layers(sp, wo, &b);
  return b;
}

Color MetallicRoughnessMaterial::dielectric_f0(const ShadingPoint& sp) const {
  double alpha = 1;
  specular_texture.eval(sp.tex, &alpha);
  const Color tint = specular_color_texture.eval(sp.tex);
  const double weight = specular * std::clamp(alpha, 0.0, 1.0);
  Color f0;
  for (int k = 0; k < 3; ++k)
    f0[k] = std::min(specular_color[k] * std::max(tint[k], 0.0), 1.0) * weight;
  return f0;
}

void MetallicRoughnessMaterial::add_layers(const ShadingPoint& sp, const Vec3& wo, Bsdf* b) const {
  b->coat = std::clamp(clearcoat * clearcoat_texture.eval(sp.tex).x, 0.0, 1.0);
  if (b->coat > 0) {
    const double r =
        std::clamp(clearcoat_roughness * clearcoat_roughness_texture.eval(sp.tex).y, 0.0, 1.0);
    // (GGX below alpha 1e-3 is a mirror that point lights would still have to hit.)
    b->coat_alpha = std::max(r * r, 1e-3);
    Vec3 n = dot(wo, sp.ng) >= 0 ? sp.ns : -sp.ns;
    if (has_clearcoat_normal) n = mapped_normal(clearcoat_normal, clearcoat_normal_scale, sp, n);
    if (dot(n, wo) <= 0) n = normalize(n - wo * (dot(n, wo) - 1e-4));
    b->coat_frame = Frame::from_normal(n);
  }
  double alpha = 1;
  const Color tint = sheen_color_texture.eval(sp.tex);
  sheen_roughness_texture.eval(sp.tex, &alpha);
  for (int k = 0; k < 3; ++k) b->sheen[k] = std::clamp(sheen_color[k] * tint[k], 0.0, 1.0);
  b->sheen_roughness = std::clamp(sheen_roughness * alpha, 0.0, 1.0);
}

std::string MetallicRoughnessMaterial::describe() const {
  std::string s(type());
  if (clearcoat > 0) s += ", clear coat";
  if (max_component(sheen_color) > 0) s += ", sheen";
  return s;
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
    {"clearcoat", ParamType::Number, "0",
     "Clear coat weight (KHR_materials_clearcoat): a GGX dielectric layer of IOR 1.5 over the "
     "material, which keeps 1 - clearcoat x Fresnel of the light.", 0, 1},
    {"clearcoat_roughness", ParamType::Number, "0",
     "The clear coat's roughness (GGX alpha = roughness^2, at least 1e-3).", 0, 1},
    {"sheen_color", ParamType::Color, "0",
     "Sheen colour (KHR_materials_sheen): Charlie's sheen (Estevez-Kulla) with Neubelt's "
     "visibility over the material, which keeps 1 - max(sheen_color) x the sheen's albedo.", 0, 1},
    {"sheen_roughness", ParamType::Number, "0",
     "The sheen's roughness (alpha = roughness^2; taken as at least 0.07).", 0, 1},
};
// clang-format on

std::unique_ptr<Material> create(const ParamValues& v) {
  auto m = std::make_unique<MetallicRoughnessMaterial>();
  m->metallic = v.number("metallic");
  m->roughness = v.number("roughness");
  m->transmission = v.number("transmission");
  m->thin = v.boolean("thin");
  m->absorption = v.color("absorption");
  m->clearcoat = v.number("clearcoat");
  m->clearcoat_roughness = v.number("clearcoat_roughness");
  m->sheen_color = v.color("sheen_color");
  m->sheen_roughness = v.number("sheen_roughness");
  return m;
}

}  // namespace

extern const MaterialKind kMetallicRoughnessKind;  // (in the list of material_kinds.cpp)
const MaterialKind kMetallicRoughnessKind{MetallicRoughnessMaterial::kType,
                                          "glTF 2.0's metallic-roughness model.", kParams, create};

}  // namespace anamorph
