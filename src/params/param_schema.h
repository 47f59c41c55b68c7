// JSON Schema (draft 2020-12) generated from parameter tables: one property schema per key
// (type, range, choices, default, description with unit) and one object schema per table
// (`additionalProperties: false`, required keys). Tables of several forms are put together by
// their owners (scene/scene_docs.cpp).
#pragma once

#include <initializer_list>
#include <span>
#include <string_view>

#include <nlohmann/json.hpp>

#include "params/params.h"

namespace anamorph {

using Json = nlohmann::ordered_json;

// Where the schema's $defs live for the parameter types that refer to shared definitions
// (ParamType::Function -> "#/$defs/org", Texture -> "#/$defs/texture", Transform ->
// "#/$defs/transform").
Json param_json_schema(const ParamSpec& spec);

// An object with these keys (and `extra` properties, already made), nothing else allowed.
// Keys without a default are required unless named in `optional`.
Json table_json_schema(std::initializer_list<std::span<const ParamSpec>> groups,
                       const Json& extra = Json::object(),
                       std::initializer_list<std::string_view> optional = {});

// The schema of a transform table (the type ParamType::Transform refers to).
Json transform_json_schema();

}  // namespace anamorph
