// Parameter tables: every camera function (and preset) declares its parameters once. The scene
// parser converts TOML values into ParamValues by these specs, validation checks ranges from
// them, and docs/--help list them from the same table.
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
};

// The Markdown table (name | type | default | range | meaning) of a parameter table, for the
// docs of functions and presets alike.
std::string params_markdown_table(std::span<const ParamSpec> params);

struct NestedFunction;
using ParamValue = std::variant<double, int64_t, bool, std::string, Vec2, Vec3, std::vector<double>,
                                std::vector<Vec3>, std::vector<std::vector<Vec3>>,
                                std::vector<std::vector<double>>, std::map<std::string, double>,
                                std::shared_ptr<const NestedFunction>>;

// Thrown by a factory when values are individually valid but inconsistent (e.g. a knot vector
// that is too short); the scene parser adds file, line and column of `key`.
struct ParamError : std::runtime_error {
  ParamError(std::string key_, const std::string& msg)
      : std::runtime_error(msg), key(std::move(key_)) {}
  std::string key;
};

// Values after parsing and range checks; every spec'd parameter with a default is present.
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
