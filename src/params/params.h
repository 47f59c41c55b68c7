// Parameter tables: every key of the scene format is declared once, here as a ParamSpec in a
// table (camera functions, presets, coins, and the scene's own tables in scene/scene_schema).
// The one walker (read_params.h) converts TOML tables into ParamValues by these specs, checks
// types, ranges and choices from them, and rejects unknown keys with a suggestion; the docs
// (param_docs.h) and the JSON Schema (param_schema.h) are generated from the same tables.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "math/input_limits.h"
#include "math/transform.h"
#include "math/vec.h"

namespace anamorph {

enum class ParamType {
  Number,      // double
  Integer,     // int64
  Bool,        // bool
  String,      // string, optionally restricted to `choices`
  Vec2,        // [a, b]
  Vec3,        // [x, y, z]
  NumberList,  // [a, b, c, ...]
  Vec3List,    // [[x,y,z], ...]
  Vec3Grid,    // [[[x,y,z], ...], ...] rows of points (control nets)
  NumberGrid,  // [[a, b, ...], ...] (weights)
  StringMap,   // { name = number, ... } (named constants)
  Function,    // { type = "...", ... } a nested origin function (e.g. dir from_surface)
  Color,       // [r, g, b] or one number (grey); components >= min
  Texture,     // a Color, or a table { type = "checker" | "grid" | "image", ... }
  Transform,   // { translate = [...], rotate = [deg, x, y, z] (or a list), scale, matrix }
};

std::string_view to_string(ParamType t);

struct ParamSpec {
  std::string_view name;
  ParamType type;
  std::string_view default_value;  // TOML text, empty = required (or "none" = optional, no default)
  std::string_view doc;
  double min = -kInf;  // inclusive bounds for Number / Integer (and each component of vectors)
  double max = kInf;
  std::span<const std::string_view> choices = {};  // for String
  bool min_exclusive = false;
  bool max_exclusive = false;
  std::string_view unit = {};  // "degrees", "pixels", "scene units", "frames", "seconds", ...
  // A default that depends on other keys (default_value is then "none"): said in the docs, e.g.
  // "2 with whitted, 8 otherwise"; the reader computes it.
  std::string_view default_note = {};
};

// `s` with its range narrowed to the world's (math/input_limits.h): every component of a vector
// or of a list or grid of vectors, and every number in scene units, lies within
// +-kMaxCoordinate. The reader checks values against this range, and the docs and the JSON
// Schema show it.
inline ParamSpec with_world_range(ParamSpec s) {
  const bool vector = s.type == ParamType::Vec2 || s.type == ParamType::Vec3 ||
                      s.type == ParamType::Vec3List || s.type == ParamType::Vec3Grid;
  if (!vector && !(s.type == ParamType::Number && s.unit == "scene units")) return s;
  if (!(s.min > -kMaxCoordinate)) s.min = -kMaxCoordinate, s.min_exclusive = false;
  if (!(s.max < kMaxCoordinate)) s.max = kMaxCoordinate, s.max_exclusive = false;
  return s;
}

struct NestedFunction;
using ParamValue = std::variant<double, int64_t, bool, std::string, Vec2, Vec3, std::vector<double>,
                                std::vector<Vec3>, std::vector<std::vector<Vec3>>,
                                std::vector<std::vector<double>>, std::map<std::string, double>,
                                std::shared_ptr<const NestedFunction>, Transform>;

// Thrown by a factory when values are individually valid but inconsistent (e.g. a knot vector
// that is too short); the scene parser adds file, line and column of `key`.
struct ParamError : std::runtime_error {
  ParamError(std::string key_, const std::string& msg)
      : std::runtime_error(msg), key(std::move(key_)) {}
  std::string key;
  // what() without a leading "key: " (some messages name their key, for callers that print only
  // what()): for callers that print the key themselves, so that it is not named twice.
  std::string message() const {
    const std::string_view w = what();
    const std::string prefix = key + ": ";
    return std::string(!key.empty() && w.starts_with(prefix) ? w.substr(prefix.size()) : w);
  }
};

// Values after parsing and range checks; every spec'd parameter with a default is present.
// (Declared before NestedFunction, which holds one.)
class ParamValues {
 public:
  void set(std::string name, ParamValue v) { values_[std::move(name)] = std::move(v); }
  bool has(std::string_view name) const { return values_.find(std::string(name)) != values_.end(); }

  double number(std::string_view name) const { return get<double>(name); }
  int64_t integer(std::string_view name) const { return get<int64_t>(name); }
  bool boolean(std::string_view name) const { return get<bool>(name); }
  const std::string& string(std::string_view name) const { return get<std::string>(name); }
  Vec2 vec2(std::string_view name) const { return get<Vec2>(name); }
  Vec3 vec3(std::string_view name) const { return get<Vec3>(name); }
  const std::vector<double>& numbers(std::string_view name) const {
    return get<std::vector<double>>(name);
  }
  const std::vector<Vec3>& vec3s(std::string_view name) const {
    return get<std::vector<Vec3>>(name);
  }
  const std::vector<std::vector<Vec3>>& vec3_grid(std::string_view name) const {
    return get<std::vector<std::vector<Vec3>>>(name);
  }
  const std::vector<std::vector<double>>& number_grid(std::string_view name) const {
    return get<std::vector<std::vector<double>>>(name);
  }
  const std::map<std::string, double>& string_map(std::string_view name) const {
    return get<std::map<std::string, double>>(name);
  }
  const NestedFunction& function(std::string_view name) const {
    return *get<std::shared_ptr<const NestedFunction>>(name);
  }
  Vec3 color(std::string_view name) const { return get<Vec3>(name); }
  const Transform& transform(std::string_view name) const { return get<Transform>(name); }
  // A Texture parameter given as a table (else it is a colour, read with color()).
  bool is_table(std::string_view name) const {
    auto it = values_.find(name);
    return it != values_.end() &&
           std::holds_alternative<std::shared_ptr<const NestedFunction>>(it->second);
  }
  const std::map<std::string, ParamValue, std::less<>>& all() const { return values_; }

 private:
  template <class T>
  const T& get(std::string_view name) const {
    auto it = values_.find(name);
    if (it == values_.end())
      throw ParamError(std::string(name), "missing required key '" + std::string(name) + "'");
    if (auto* p = std::get_if<T>(&it->second)) return *p;
    throw ParamError(std::string(name),
                     "internal: key '" + std::string(name) + "' has another type");
  }
  std::map<std::string, ParamValue, std::less<>> values_;
};

struct NestedFunction {
  std::string type;
  ParamValues values;
};

}  // namespace anamorph
