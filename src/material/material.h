// Materials: what a surface does with light. The renderer knows a material only through this
// interface; each kind is a class of its own (whitted.h, metallic_roughness.h, ...), made by its
// `type` name from the registry (material_kinds.h). Nothing outside this folder asks which kind
// a material is.
//
// What a kind answers: the BSDF at a shading point (one virtual call per hit; the BSDF is lobes as
// data, evaluated without further virtual calls, bsdf.h), what Whitted's tracing needs beyond it
// (the shadow transmission of see-through surfaces, whether rays go on from a hit), what form
// factors need (the diffuse reflectance), whether it reads textures, and a description.
// What every kind has is data here: the common keys of [[material]] (material_common_params())
// and glTF's core material (emission, normal map, alpha).
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "material/bsdf.h"
#include "material/texture.h"

namespace anamorph {

// Where a ray meets a surface, as a material sees it (the renderer fills it from its hit).
struct ShadingPoint {
  Vec3 p;           // world space
  Vec3 ng, ns;      // geometric and shading normals as the surface has them (unit, not flipped)
  Vec3 dpdu, dpdv;  // the surface's derivatives (a normal map's tangent frame)
  // uv, the pixel's footprint and what procedural textures read. Left default-constructed when
  // the material is not textured() (constant textures never read it).
  TexCoord tex;
};

class Material {
 public:
  virtual ~Material() = default;

  // ---- What every kind has ----
  std::string name;
  Texture base_color = Texture::constant({0.8, 0.8, 0.8});  // diffuse colour / glTF baseColor
  Texture emission = Texture::constant({0, 0, 0});  // radiance emitted (x emission_strength)
  double emission_strength = 1;
  double ior = 1.5;          // index of refraction (also used for Fresnel)
  bool double_sided = true;  // false: emits only on the front
  Texture normal_map;        // tangent-space normal map (Kind::Constant = none)
  bool has_normal_map = false;
  double normal_scale = 1;
  enum class AlphaMode { Opaque, Mask, Blend };
  AlphaMode alpha_mode = AlphaMode::Opaque;
  double alpha_cutoff = 0.5;

  // ---- What each kind answers ----
  // Its name in the registry: the `type` of [[material]].
  virtual std::string_view type() const = 0;
  // For `anamorph info`: the type, and what else a reader should know.
  virtual std::string describe() const { return std::string(type()); }
  // The BSDF at sp for light leaving toward wo (unit, away from the surface).
  virtual Bsdf bsdf(const ShadingPoint& sp, const Vec3& wo) const = 0;
  // The fraction of light reflected diffusely, from constant parameters (a texture's value):
  // what form factors and radiosity take as the surface's reflectance.
  virtual Color diffuse_reflectance() const = 0;
  // Whitted's see-through surfaces: the factor a shadow ray crossing the surface keeps (as in
  // Whitted's paper and POV-Ray: unrefracted). 0: opaque, which also keeps the surface out of
  // the acceleration structure's see-through set.
  virtual double shadow_transmission() const = 0;
  // Whether Whitted's tracing may go on from a hit on it (mirror reflection or refraction): such
  // hits need the pixel's footprint, which the new rays carry along.
  virtual bool spawns_specular_rays() const = 0;
  // Some texture is not a constant: shading reads texture coordinates (and their footprint).
  // Kinds with textures of their own add them.
  virtual bool textured() const {
    return base_color.kind != Texture::Kind::Constant || has_normal_map ||
           emission.kind != Texture::Kind::Constant;
  }

  // ---- Derived from the common data ----
  bool is_emissive() const {
    return emission.kind != Texture::Kind::Constant || max_component(emission.value) > 0;
  }
  // Alpha-masked: hits where the base colour's alpha falls below the cutoff are not hits.
  // (Blend is transparency in the BSDF instead: bsdf_frame's opacity.)
  bool alpha_masked() const {
    return alpha_mode == AlphaMode::Mask && base_color.kind == Texture::Kind::Image;
  }
  // Alpha blend: a share of the light goes straight on (the BSDF's opacity); the path tracer's
  // shadow rays pass such surfaces too, keeping 1 - opacity_at() of the light.
  bool blends() const { return alpha_mode == AlphaMode::Blend; }
  // The blended surface's opacity at tc: its alpha (the base colour's factor x texture), in [0, 1].
  double opacity_at(const TexCoord& tc) const;
  bool opaque_at(const TexCoord& tc) const {
    double alpha = 1;
    base_color.eval(tc, &alpha);
    return !(alpha < alpha_cutoff);
  }

 protected:
  // A BSDF without lobes, in the shading frame at sp (normal-mapped, facing wo) with the ior:
  // where each kind's bsdf() starts.
  Bsdf bsdf_frame(const ShadingPoint& sp, const Vec3& wo) const;
  // ns (unit, the side of sp's normals that faces the viewer) bent by a tangent-space normal map.
  static Vec3 mapped_normal(const Texture& map, double scale, const ShadingPoint& sp, Vec3 ns);
};

// A scene's materials, by index (meshes and shapes name theirs by index).
using MaterialList = std::vector<std::unique_ptr<const Material>>;

}  // namespace anamorph
