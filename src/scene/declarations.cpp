#include "scene/declarations.h"

#include <cmath>

#include "camera/coins.h"
#include "camera/functions.h"
#include "camera/presets.h"
#include "scene/scene_schema.h"

namespace anamorph {

namespace {

Json bound(double x) { return std::isinf(x) ? Json(nullptr) : Json(x); }

Json spec_json(const ParamSpec& declared) {
  const ParamSpec p = with_world_range(declared);
  const bool required = p.default_value.empty();
  const bool optional = p.default_value == "none";
  Json choices = Json::array();
  for (std::string_view c : p.choices) choices.push_back(std::string(c));
  return {{"name", std::string(p.name)},
          {"type", std::string(to_string(p.type))},
          {"required", required},
          {"default", required || optional ? Json(nullptr) : Json(std::string(p.default_value))},
          {"default_note", std::string(p.default_note)},
          {"doc", std::string(p.doc)},
          {"unit", std::string(p.unit)},
          {"min", bound(p.min)},
          {"max", bound(p.max)},
          {"min_exclusive", p.min_exclusive},
          {"max_exclusive", p.max_exclusive},
          {"choices", choices}};
}

Json specs(std::span<const ParamSpec> ps) {
  Json l = Json::array();
  for (const ParamSpec& p : ps) l.push_back(spec_json(p));
  return l;
}

template <class Infos>
Json forms(const Infos& infos) {
  Json d = Json::object();
  for (const auto& f : infos)
    d[std::string(f.name)] = {{"doc", std::string(f.doc)}, {"params", specs(f.params)}};
  return d;
}

// Every table of the scene format by its key: its documentation, whether it is an array of
// tables ([[key]]), its selector key ("type") and the keys of each form.
Json tables() {
  Json d = Json::object();
  for (const TableSchema* t : scene_tables()) {
    Json variants = Json::object();
    for (const TableVariant& v : t->variants)
      variants[std::string(v.name)] = {{"doc", std::string(v.doc)}, {"params", specs(v.params)}};
    d[std::string(t->key)] = {{"doc", std::string(t->doc)},
                              {"array", t->array},
                              {"selector", std::string(t->selector)},
                              {"common", specs(t->common)},
                              {"variants", variants}};
  }
  return d;
}

}  // namespace

Json declarations_json() {
  return {{"presets", forms(camera_presets())},      {"org", forms(org_functions())},
          {"dir", forms(dir_functions())},           {"coin", specs(coin_params())},
          {"camera", specs(camera_common_params())}, {"image", specs(image_schema().common)},
          {"render", specs(render_schema().common)}, {"tables", tables()}};
}

}  // namespace anamorph
