// What is generated from the declarations: docs/scene-format.md's key tables, the function
// reference docs/functions.md, and the JSON Schema of the whole format (`anamorph schema`).
#include <fmt/format.h>

#include <sstream>
#include <string>

#include "camera/coins.h"
#include "camera/functions.h"
#include "camera/presets.h"
#include "params/param_docs.h"
#include "params/param_schema.h"
#include "scene/scene_schema.h"

namespace anamorph {

namespace {

std::string bracketed(const TableSchema& t) {
  return t.array ? fmt::format("[[{}]]", t.key) : fmt::format("[{}]", t.key);
}

void table_markdown(std::ostringstream& os, const TableSchema& t) {
  os << "### `" << (t.key == "texture" ? std::string("texture tables") : bracketed(t)) << "`\n\n"
     << t.doc << "\n\n"
     << params_markdown_table(t.common) << "\n";
  for (const TableVariant& v : t.variants) {
    os << "#### `" << t.selector << " = \"" << v.name << "\"`\n\n" << v.doc << "\n\n";
    if (v.params.empty())
      os << "No keys of its own.\n\n";
    else
      os << params_markdown_table(v.params) << "\n";
  }
}

}  // namespace

std::string scene_format_tables_markdown() {
  std::ostringstream os;
  os << "### Top level\n\n" << params_markdown_table(top_level_params()) << "\n";
  for (const TableSchema* t : scene_tables()) table_markdown(os, *t);
  os << "### `[camera]`: keys of every camera\n\n"
     << "Besides these, a camera takes `preset` and its preset's keys, or `org` and `dir` "
        "functions, or `gltf_camera` (see cameras.md and functions.md), and `[[camera.coin]]` "
        "entries (see coins.md).\n\n";
  const ParamSpec preset[] = {camera_preset_spec()};
  os << params_markdown_table(preset) << "\n"
     << params_markdown_table(camera_common_params()) << "\n";
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

// One branch per form: its selector fixed (optional for the default form), its keys and the
// common ones.
template <class Forms, class KeysOf>
Json one_of_forms(const Forms& forms, std::string_view selector, std::string_view default_form,
                  std::span<const ParamSpec> common, const Json& extra, KeysOf keys_of) {
  Json branches = Json::array();
  for (const auto& f : forms) {
    Json sel = {{"const", std::string(f.name)}, {"description", std::string(f.doc)}};
    Json props = extra;
    props[std::string(selector)] = sel;
    Json branch = table_json_schema({common, keys_of(f)}, props);
    if (f.name != default_form) branch["required"].push_back(std::string(selector));
    branches.push_back(branch);
  }
  return {{"oneOf", branches}};
}

Json scene_table_json(const TableSchema& t, std::string_view default_form = {}) {
  if (t.variants.empty()) return table_json_schema({t.common});
  // The selector's own spec is replaced by a constant per branch.
  std::vector<ParamSpec> common;
  for (const ParamSpec& s : t.common)
    if (s.name != t.selector) common.push_back(s);
  return one_of_forms(t.variants, t.selector, default_form, common, Json::object(),
                      [](const TableVariant& v) { return v.params; });
}

Json camera_json() {
  const Json coins = {{"type", "array"}, {"items", {{"$ref", "#/$defs/coin"}}}};
  const Json preset_extra = {{"coin", coins}};
  Json presets = one_of_forms(camera_presets(), "preset", "perspective", camera_common_params(),
                              preset_extra, [](const PresetInfo& p) { return p.params; });
  Json composed = table_json_schema(
      {camera_common_params()},
      {{"org", {{"$ref", "#/$defs/org"}}}, {"dir", {{"$ref", "#/$defs/dir"}}}, {"coin", coins}});
  composed["required"] = {"org", "dir"};
  Json branches = presets["oneOf"];
  branches.push_back(composed);
  Json gltf = table_json_schema({camera_common_params()}, {{"coin", coins}});
  gltf["required"] = {"gltf_camera"};
  branches.push_back(gltf);
  // A preset table may hold gltf_camera too in the common keys: keep the forms apart.
  for (size_t i = 0; i + 2 < branches.size(); ++i)
    branches[i]["not"] = {{"required", {"gltf_camera"}}};
  return {{"description", "The camera: a preset, an org/dir composition or a glTF camera."},
          {"oneOf", branches}};
}

template <class Infos>
Json functions_json(const Infos& infos) {
  return one_of_forms(infos, "type", "", {}, Json::object(),
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
  props["material"] = array_of(scene_table_json(material_schema(), "whitted"));
  props["object"] = array_of(scene_table_json(object_schema()));
  props["light"] = array_of(scene_table_json(light_schema()));
  props["environment"] = scene_table_json(environment_schema());
  props["animate"] = array_of(animate_json());
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
