// What is generated from the declarations: docs/scene-format.md's key tables, the function
// reference docs/functions.md, and the JSON Schema of the whole format (`anamorph schema`).
#include <fmt/format.h>

#include <sstream>
#include <stdexcept>
#include <string>

#include "camera/coins.h"
#include "camera/functions.h"
#include "camera/presets.h"
#include "material/material_kinds.h"
#include "params/param_docs.h"
#include "params/param_schema.h"
#include "scene/scene_schema.h"

namespace anamorph {

namespace {

void table_markdown(std::ostringstream& os, const TableSchema& t) {
  os << params_markdown_table(t.common) << "\n";
  for (const TableVariant& v : t.variants) {
    os << "#### `" << t.selector << " = \"" << v.name << "\"`\n\n" << v.doc << "\n\n";
    if (v.params.empty())
      os << "No keys of its own.\n\n";
    else
      os << params_markdown_table(v.params) << "\n";
  }
}

constexpr std::string_view kBlocks[] = {
    "top",         "image",       "render",      "camera",  "material",  "texture",
    "object",      "light",       "environment", "animate", "animation", "camera.constraint",
    "camera.free", "camera.solve"};

}  // namespace

std::span<const std::string_view> scene_doc_blocks() { return kBlocks; }

std::string scene_doc_block(std::string_view name) {
  std::ostringstream os;
  if (name == "top") {
    os << params_markdown_table(top_level_params()) << "\n";
  } else if (name == "camera") {
    const ParamSpec preset[] = {camera_preset_spec()};
    os << params_markdown_table(preset) << "\n"
       << params_markdown_table(camera_common_params()) << "\n";
  } else {
    for (const TableSchema* t : scene_tables())
      if (t->key == name) table_markdown(os, *t);
  }
  return os.str();
}

std::string function_reference_markdown() {
  std::ostringstream os;
  os << function_params_markdown();
  os << "## Presets (`camera.preset`)\n\n"
        "Each is a composition of the functions above, filled in from these keys.\n\n";
  for (const PresetInfo& p : camera_presets())
    os << "### preset `" << p.name << "`\n\n"
       << p.doc << "\n\n"
       << preset_params_markdown(p) << "\n";
  os << "## Centers of interest (`[[camera.coin]]`)\n\n"
     << params_markdown_table(coin_params()) << "\n";
  return os.str();
}

namespace {

std::pair<size_t, size_t> block_span(const std::string& doc, std::string_view name) {
  const std::string open = fmt::format("<!-- generated:{} -->\n", name);
  const std::string close = fmt::format("<!-- /generated:{} -->", name);
  const size_t a = doc.find(open), b = doc.find(close);
  if (a == std::string::npos || b == std::string::npos || b < a)
    return {std::string::npos, std::string::npos};
  return {a + open.size(), b};
}

}  // namespace

std::string with_generated_block(const std::string& doc, std::string_view name,
                                 const std::string& content) {
  const auto [a, b] = block_span(doc, name);
  if (a == std::string::npos)
    throw std::runtime_error(fmt::format("no <!-- generated:{} --> block", name));
  return doc.substr(0, a) + content + doc.substr(b);
}

std::string generated_block(const std::string& doc, std::string_view name) {
  const auto [a, b] = block_span(doc, name);
  return a == std::string::npos ? std::string() : doc.substr(a, b - a);
}

namespace {

// One `if {selector: name} then {that form's table}` per form (not oneOf: a validator then names
// the bad key inside the form, as the reader does, instead of "not valid under any schema").
// The default form's `if` also holds when the selector is absent.
template <class Forms, class KeysOf>
Json forms_by_selector(const Forms& forms, std::string_view selector, std::string_view default_form,
                       std::span<const ParamSpec> common, const Json& extra, KeysOf keys_of) {
  const std::string sel(selector);
  Json names = Json::array(), branches = Json::array();
  for (const auto& f : forms) {
    names.push_back(std::string(f.name));
    Json props = extra;
    props[sel] = {{"const", std::string(f.name)}, {"description", std::string(f.doc)}};
    Json when = {{"properties", {{sel, {{"const", std::string(f.name)}}}}}};
    if (f.name != default_form) when["required"] = {sel};
    branches.push_back({{"if", when}, {"then", table_json_schema({common, keys_of(f)}, props)}});
  }
  Json j = {{"type", "object"}, {"properties", {{sel, {{"enum", names}}}}}, {"allOf", branches}};
  if (default_form.empty()) j["required"] = {sel};
  return j;
}

Json scene_table_json(const TableSchema& t, std::string_view default_form = {}) {
  if (t.variants.empty()) return table_json_schema({t.common});
  // The selector's own spec is replaced by a constant per branch.
  std::vector<ParamSpec> common;
  for (const ParamSpec& s : t.common)
    if (s.name != t.selector) common.push_back(s);
  return forms_by_selector(t.variants, t.selector, default_form, common, Json::object(),
                           [](const TableVariant& v) { return v.params; });
}

// The camera's three forms: org/dir functions (when either is given), a glTF camera alone (when
// gltf_camera is given without a preset or functions), else a preset (perspective when none is
// named). gltf_camera may give the other two their pose.
Json camera_json() {
  const Json coins = {{"type", "array"}, {"items", {{"$ref", "#/$defs/coin"}}}};
  // Every form takes the coins and the goals of `anamorph solve`.
  const auto array_of = [](const Json& item) { return Json{{"type", "array"}, {"items", item}}; };
  Json tables = {{"coin", coins},
                 {"constraint", array_of(scene_table_json(constraint_schema()))},
                 {"free", array_of(table_json_schema({free_schema().common}))},
                 {"solve", table_json_schema({solve_schema().common})}};
  const Json composed_when = {{"anyOf", {{{"required", {"org"}}}, {{"required", {"dir"}}}}}};
  const Json gltf_when = {{"required", {"gltf_camera"}},
                          {"not", {{"anyOf", {{{"required", {"preset"}}}, composed_when}}}}};
  Json presets =
      forms_by_selector(camera_presets(), "preset", "perspective", camera_common_params(), tables,
                        [](const PresetInfo& p) { return p.params; });
  for (Json& branch : presets["allOf"])
    branch["if"]["not"] = {{"anyOf", {composed_when, gltf_when}}};
  Json composed_tables = tables;
  composed_tables["org"] = {{"$ref", "#/$defs/org"}};
  composed_tables["dir"] = {{"$ref", "#/$defs/dir"}};
  Json composed = table_json_schema({camera_common_params()}, composed_tables);
  composed["required"] = {"org", "dir"};
  presets["allOf"].push_back({{"if", composed_when}, {"then", composed}});
  Json gltf = table_json_schema({camera_common_params()}, tables);
  presets["allOf"].push_back({{"if", gltf_when}, {"then", gltf}});
  presets["properties"].erase("preset");  // (named in each preset's branch)
  presets["description"] = "The camera: a preset, an org/dir composition or a glTF camera.";
  return presets;
}

template <class Infos>
Json functions_json(const Infos& infos) {
  return forms_by_selector(infos, "type", "", {}, Json::object(),
                           [](const auto& f) { return f.params; });
}

Json animate_json() {
  const Json value = {{"oneOf", {{{"type", "number"}}, {{"type", "array"}}}}};
  Json j = table_json_schema({animate_schema().common});
  j["properties"]["keys"] = {{"description", "[[frame, value], ...] with increasing frames."},
                             {"type", "array"},
                             {"items",
                              {{"type", "array"},
                               {"prefixItems", {{{"type", "number"}}, value}},
                               {"minItems", 2},
                               {"maxItems", 2}}}};
  return j;
}

}  // namespace

std::string scene_json_schema() {
  const auto array_of = [](const Json& item) { return Json{{"type", "array"}, {"items", item}}; };
  Json props = Json::object();
  props["include"] = {{"description", std::string(top_level_params()[0].doc)},
                      {"oneOf", {{{"type", "string"}}, array_of({{"type", "string"}})}}};
  props["image"] = scene_table_json(image_schema());
  props["render"] = scene_table_json(render_schema());
  props["camera"] = {{"$ref", "#/$defs/camera"}};
  props["material"] = array_of(scene_table_json(material_schema(), default_material_type()));
  props["object"] = array_of(scene_table_json(object_schema()));
  props["light"] = array_of(scene_table_json(light_schema()));
  props["environment"] = scene_table_json(environment_schema());
  props["animate"] = array_of(animate_json());
  props["animation"] = scene_table_json(animation_schema());
  Json defs = Json::object();
  defs["camera"] = camera_json();
  defs["org"] = functions_json(org_functions());
  defs["dir"] = functions_json(dir_functions());
  defs["coin"] = table_json_schema({coin_params()});
  defs["texture"] = scene_table_json(texture_schema());
  defs["transform"] = transform_json_schema();
  const Json schema = {{"$schema", "https://json-schema.org/draft/2020-12/schema"},
                       {"$id", "https://anamorph.invalid/scene.schema.json"},
                       {"title", "anamorph scene"},
                       {"description",
                        "The anamorph scene format (TOML), generated from the declared parameter "
                        "tables by `anamorph schema`."},
                       {"type", "object"},
                       {"properties", props},
                       {"additionalProperties", false},
                       {"$defs", defs}};
  return schema.dump(2) + "\n";
}

}  // namespace anamorph
