// The one list of material kinds (adding a kind = its file, and its line in kBuiltin below), the
// keys every kind takes, and making a material from its keys.
#include "material/material_kinds.h"

#include <fmt/format.h>

#include <atomic>
#include <stdexcept>
#include <string>
#include <vector>

#include "params/read_params.h"

namespace anamorph {

extern const MaterialKind kWhittedKind;            // whitted.cpp
extern const MaterialKind kMetallicRoughnessKind;  // metallic_roughness.cpp
extern const MaterialKind kUnlitKind;              // unlit.cpp

namespace {

const MaterialKind* const kBuiltin[] = {&kWhittedKind, &kMetallicRoughnessKind, &kUnlitKind};

struct Registry {
  std::vector<const MaterialKind*> kinds{std::begin(kBuiltin), std::end(kBuiltin)};
  std::atomic<bool> read{false};  // once read, the list stays as it is
};
Registry& registry() {
  static Registry r;
  return r;
}

std::string kind_names() {
  std::string s;
  for (const MaterialKind* k : material_kinds())
    s += (s.empty() ? "" : ", ") + std::string(k->name);
  return s;
}

}  // namespace

std::span<const MaterialKind* const> material_kinds() {
  Registry& r = registry();
  r.read.store(true, std::memory_order_relaxed);
  return r.kinds;
}

const MaterialKind* find_material_kind(std::string_view name) {
  for (const MaterialKind* k : material_kinds())
    if (k->name == name) return k;
  return nullptr;
}

bool add_material_kind(const MaterialKind& kind) {
  Registry& r = registry();
  if (r.read.load(std::memory_order_relaxed))
    throw std::logic_error("material kind '" + std::string(kind.name) +
                           "' added after the kinds were read");
  for (const MaterialKind* k : r.kinds)
    if (k->name == kind.name)
      throw std::logic_error("material kind '" + std::string(kind.name) + "' added twice");
  r.kinds.push_back(&kind);
  return true;
}

std::span<const ParamSpec> material_common_params() {
  static const std::vector<std::string_view> names = [] {
    std::vector<std::string_view> v;
    for (const MaterialKind* k : material_kinds()) v.push_back(k->name);
    return v;
  }();
  // clang-format off
  static const ParamSpec specs[] = {
      {"name", ParamType::String, "", "Referred to by objects."},
      {"type", ParamType::String, "\"whitted\"",
       "The kind of material; each kind's own keys are listed under its name below.", -kInf, kInf,
       names},
      {"color", ParamType::Texture, "0.8",
       "Diffuse colour / glTF base colour: the fraction of light reflected, per channel "
       "(radiosity takes it as the reflectance).", 0, 1},
      {"emission", ParamType::Texture, "0",
       "Emitted radiance; emissive surfaces are light sources.", 0, kMaxRadiance},
      {"emission_strength", ParamType::Number, "1", "Multiplies `emission`.", 0, kMaxRadiance},
      {"ior", ParamType::Number, "1.5", "Index of refraction.", 1, 10},
      {"double_sided", ParamType::Bool, "true", "One-sided emitters emit only on the front."},
  };
  // clang-format on
  return specs;
}

std::string_view default_material_type() {
  for (const ParamSpec& s : material_common_params())
    if (s.name == "type") return s.default_value.substr(1, s.default_value.size() - 2);  // (quoted)
  return {};
}

std::unique_ptr<Material> make_material(const ParamValues& v,
                                        const MaterialTextureReader& texture) {
  const MaterialKind* kind = find_material_kind(v.string("type"));
  if (!kind)
    throw ParamError("type", fmt::format("type: unknown material type \"{}\" (valid: {})",
                                         v.string("type"), kind_names()));
  // (The textures first: a file that cannot be read is reported before the kind's checks.)
  Texture color = texture("color", true);
  Texture emission = texture("emission", true);
  std::unique_ptr<Material> m = kind->create(v);
  m->name = v.string("name");
  m->base_color = std::move(color);
  m->emission = std::move(emission);
  m->emission_strength = v.number("emission_strength");
  m->ior = v.number("ior");
  m->double_sided = v.boolean("double_sided");
  return m;
}

std::unique_ptr<Material> make_material(const toml::table& t) {
  const std::string type = t["type"].value_or(std::string(default_material_type()));
  const MaterialKind* kind = find_material_kind(type);
  if (!kind)
    throw ParamError(
        "type", fmt::format("type: unknown material type \"{}\" (valid: {})", type, kind_names()));
  ParamWalk w;
  w.hooks.fail = [](const toml::node&, std::string_view key, const std::string& msg) {
    if (msg == "is required")
      throw ParamError(std::string(key), fmt::format("missing required key '{}'", key));
    throw ParamError(std::string(key), fmt::format("{}: {}", key, msg));
  };
  w.hooks.nested = [](const toml::table&,
                      const ParamSpec& spec) -> std::shared_ptr<const NestedFunction> {
    throw ParamError(std::string(spec.name),
                     fmt::format("{}: texture tables are read from scene files", spec.name));
  };
  w.unknown_key = [](const toml::key& k, const std::string& msg) {
    throw ParamError(std::string(k.str()), fmt::format("{}: {}", k.str(), msg));
  };
  const ParamValues v = read_params(t, {material_common_params(), kind->params}, w);
  return make_material(v,
                       [&](std::string_view key, bool) { return Texture::constant(v.color(key)); });
}

std::unique_ptr<Material> make_material(std::string_view toml_text) {
  toml::table t;
  try {
    t = toml::parse(toml_text);
  } catch (const toml::parse_error& e) {
    throw ParamError("", "invalid TOML: " + std::string(e.description()));
  }
  return make_material(t);
}

}  // namespace anamorph
