#include "params/param_schema.h"

#include <string>

#include <toml++/toml.h>

#include "params/param_docs.h"

namespace anamorph {

namespace {

Json node_to_json(const toml::node& n) {
  if (const auto* t = n.as_table()) {
    Json o = Json::object();
    for (const auto& [k, v] : *t) o[std::string(k.str())] = node_to_json(v);
    return o;
  }
  if (const auto* a = n.as_array()) {
    Json o = Json::array();
    for (const auto& e : *a) o.push_back(node_to_json(e));
    return o;
  }
  if (n.is_integer()) return *n.value<int64_t>();
  if (n.is_floating_point()) return *n.value<double>();
  if (n.is_boolean()) return *n.value<bool>();
  if (n.is_string()) return *n.value<std::string>();
  return nullptr;
}

// A number with the spec's bounds (infinite bounds left out).
Json number(const ParamSpec& s, const char* type = "number") {
  Json j = {{"type", type}};
  if (s.min != -kInf) j[s.min_exclusive ? "exclusiveMinimum" : "minimum"] = s.min;
  if (s.max != kInf) j[s.max_exclusive ? "exclusiveMaximum" : "maximum"] = s.max;
  return j;
}

Json array_of(const Json& item, int n = -1) {
  Json j = {{"type", "array"}, {"items", item}};
  if (n >= 0) j["minItems"] = n, j["maxItems"] = n;
  return j;
}

Json value_schema(const ParamSpec& s) {
  switch (s.type) {
    case ParamType::Number:
      return number(s);
    case ParamType::Integer:
      return number(s, "integer");
    case ParamType::Bool:
      return {{"type", "boolean"}};
    case ParamType::String: {
      Json j = {{"type", "string"}};
      if (!s.choices.empty()) {
        j["enum"] = Json::array();
        for (auto c : s.choices) j["enum"].push_back(std::string(c));
      }
      return j;
    }
    case ParamType::Vec2:
      return array_of(number(s), 2);
    case ParamType::Vec3:
      return array_of(number(s), 3);
    case ParamType::NumberList:
      return array_of(number(s));
    case ParamType::Vec3List:
      return array_of(array_of(number(s), 3));
    case ParamType::Vec3Grid:
      return array_of(array_of(array_of(number(s), 3)));
    case ParamType::NumberGrid:
      return array_of(array_of(number(s)));
    case ParamType::StringMap:
      return {{"type", "object"}, {"additionalProperties", {{"type", "number"}}}};
    case ParamType::Function:
      return {{"$ref", "#/$defs/org"}};
    case ParamType::Color:
      return {{"oneOf", {number(s), array_of(number(s), 3)}}};
    case ParamType::Texture:
      return {{"oneOf", {number(s), array_of(number(s), 3), {{"$ref", "#/$defs/texture"}}}}};
    case ParamType::Transform:
      return {{"$ref", "#/$defs/transform"}};
  }
  return Json::object();
}

// A TOML default written as text ("[0, 1, 0]", "\"box\"") as JSON.
Json toml_text_to_json(std::string_view text) {
  const toml::table t = toml::parse("v = " + std::string(text));
  return node_to_json(*t.get("v"));
}

}  // namespace

Json param_json_schema(const ParamSpec& declared) {
  const ParamSpec s = with_world_range(declared);
  Json j = value_schema(s);
  std::string doc(s.doc);
  if (!s.unit.empty()) doc += " Unit: " + std::string(s.unit) + ".";
  if (!s.default_note.empty()) doc += " Default: " + std::string(s.default_note) + ".";
  j["description"] = doc;
  if (!s.default_value.empty() && s.default_value != "none")
    j["default"] = toml_text_to_json(s.default_value);
  return j;
}

Json table_json_schema(std::initializer_list<std::span<const ParamSpec>> groups, const Json& extra,
                       std::initializer_list<std::string_view> optional) {
  Json props = Json::object(), required = Json::array();
  for (const auto& g : groups)
    for (const ParamSpec& s : g) {
      props[std::string(s.name)] = param_json_schema(s);
      bool opt = false;
      for (std::string_view o : optional) opt |= o == s.name;
      if (s.default_value.empty() && !opt) required.push_back(std::string(s.name));
    }
  for (const auto& [k, v] : extra.items()) props[k] = v;
  Json j = {{"type", "object"}, {"properties", props}};
  if (!required.empty()) j["required"] = required;
  j["additionalProperties"] = false;
  return j;
}

Json transform_json_schema() {
  const Json num = {{"type", "number"}};
  const Json rotation = array_of(num, 4);
  return {{"type", "object"},
          {"description",
           "Applied to points as scale, then rotate, then translate (matrix first of all)."},
          {"properties",
           {{"matrix",
             {{"description", "Row-major 4x4, applied before the others."},
              {"type", "array"},
              {"items", num},
              {"minItems", 16},
              {"maxItems", 16}}},
            {"scale", {{"description", "Non-zero factors."}, {"oneOf", {num, array_of(num, 3)}}}},
            {"rotate",
             {{"description",
               "[degrees, ax, ay, az] about an axis through the origin, or a list "
               "of them applied in order."},
              {"oneOf", {rotation, array_of(rotation)}}}},
            {"translate", array_of(num, 3)}}},
          {"additionalProperties", false}};
}

}  // namespace anamorph
