// The material kinds by name: the `type` of [[material]]. Each kind's file defines its class, its
// own keys (ParamSpec) and its MaterialKind; the one list is in material_kinds.cpp. The scene
// reader, the docs, the JSON Schema and the editor take the kinds and their keys from here.
#pragma once

#include <functional>
#include <memory>
#include <span>
#include <string_view>

#include <toml++/toml.h>

#include "material/material.h"
#include "params/params.h"

namespace anamorph {

// The largest value of a key that is (a factor of) emitted radiance: emission and its strength,
// the lights' colours and strengths, the environment, texture colours. The film keeps
// single-precision sums (at most 3.4e38), and form factors multiply emission by pi in double: a
// key beyond 1e38 is an error at load; a product of two that overflows the film is dropped per
// sample and counted as a NaN/Inf sample.
constexpr double kMaxRadiance = 1e38;

struct MaterialKind {
  std::string_view name;  // the `type`
  std::string_view doc;
  std::span<const ParamSpec> params;  // its own keys (every kind also takes the common ones)
  // The material from its keys' values (checked and defaulted; the common keys are set by the
  // caller). Throws ParamError for values that are valid alone but not together.
  std::unique_ptr<Material> (*create)(const ParamValues& values);
};

// Every kind, in the order the docs list them.
std::span<const MaterialKind* const> material_kinds();
const MaterialKind* find_material_kind(std::string_view name);
// The kind of a [[material]] without `type`.
std::string_view default_material_type();

// Adds a kind defined outside this folder (a test's): call it before anything reads the kinds,
// i.e. while static objects are initialized (`const bool added = add_material_kind(k);`).
// Throws std::logic_error later, or for a name already taken. Returns true.
bool add_material_kind(const MaterialKind& kind);

// The keys of every kind (name, type, color, emission, emission_strength, ior, double_sided).
std::span<const ParamSpec> material_common_params();

// A texture key's value as a Texture; the scene reader resolves tables and image files.
using MaterialTextureReader = std::function<Texture(std::string_view key, bool srgb)>;

// The material of values read by {material_common_params(), its kind's params}: the kind `type`
// names makes it, and the common keys are set (textures through `texture`). Throws ParamError.
std::unique_ptr<Material> make_material(const ParamValues& values,
                                        const MaterialTextureReader& texture);
// The same from a TOML table or text, every key checked and defaulted as in a scene file, colours
// only (no texture tables): make_material("name = \"m\"\nreflectivity = 1"). Throws ParamError.
std::unique_ptr<Material> make_material(const toml::table& t);
std::unique_ptr<Material> make_material(std::string_view toml_text);

}  // namespace anamorph
