// The `whitted` material kind: its keys, its BSDF and its registry entry.
#include "material/whitted.h"

#include <algorithm>

#include "material/material_kinds.h"

namespace anamorph {

Bsdf WhittedMaterial::bsdf(const ShadingPoint& sp, const Vec3& wo) const {
  Bsdf b = bsdf_frame(sp, wo);
  const Color base = base_color.eval(sp.tex);
  b.diffuse = base * (diffuse * std::max(0.0, 1 - reflectivity - transmission));
  b.phong = specular;
  b.phong_exponent = exponent;
  b.mirror = Color(reflectivity);
  b.transmission = transmission;
  return b;
}

namespace {

// clang-format off
const ParamSpec kParams[] = {
    {"diffuse", ParamType::Number, "1",
     "Diffuse weight. The diffuse part is also scaled by 1 - reflectivity - transmission.", 0, 1},
    {"specular", ParamType::Color, "0", "Phong highlight colour ks (a normalized Phong lobe).", 0,
     kInf},
    {"exponent", ParamType::Number, "50", "Phong exponent.", 0, kInf},
    {"reflectivity", ParamType::Number, "0", "Perfect mirror reflection weight.", 0, 1},
    {"transmission", ParamType::Number, "0",
     "Smooth dielectric (refraction with Fresnel) weight; reflectivity + transmission <= 1.", 0,
     1},
};
// clang-format on

std::unique_ptr<Material> create(const ParamValues& v) {
  auto m = std::make_unique<WhittedMaterial>();
  m->diffuse = v.number("diffuse");
  m->specular = v.color("specular");
  m->exponent = v.number("exponent");
  m->reflectivity = v.number("reflectivity");
  m->transmission = v.number("transmission");
  if (m->reflectivity + m->transmission > 1)
    throw ParamError("transmission",
                     "reflectivity + transmission must not exceed 1 (energy conservation)");
  return m;
}

}  // namespace

extern const MaterialKind kWhittedKind;  // (in the list of material_kinds.cpp)
const MaterialKind kWhittedKind{
    WhittedMaterial::kType, "The paper's model: diffuse, Phong highlight, mirror and refraction.",
    kParams, create};

}  // namespace anamorph
