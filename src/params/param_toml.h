// TOML values as parameter values (params.h): the one conversion behind the walker read_params
// (the scene, with file positions; the registry's make_org, make_dir, make_preset, make_coin,
// with ParamError). Hooks say how each reports an error, where a `file` parameter points, and
// how it reads a nested table (a camera function, a texture).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include <toml++/toml.h>

#include "params/params.h"

namespace anamorph {

// The closest candidate by edit distance, or "" when nothing is close.
std::string suggest(std::string_view word, std::span<const std::string> candidates);
// "\"a\", \"b\"" for messages.
std::string join_choices(std::span<const std::string_view> choices);

// A number (integer or float), or nullopt.
std::optional<double> toml_number(const toml::node& n);
// An integer, also from a whole float below 9e15, or nullopt.
std::optional<int64_t> toml_integer(const toml::node& n);
// "a string", "an array", ... for messages.
std::string toml_type_name(const toml::node& n);
// Why v is not a finite number in the range from lo to hi (open ends when *_exclusive), e.g.
// "value -1 is out of range (must be >= 0)"; "" when it is.
std::string range_error(double v, double lo, double hi, bool lo_exclusive = false,
                        bool hi_exclusive = false);

struct ParamTomlHooks {
  // Reports that the value `at` of parameter `key` is bad; must throw.
  std::function<void(const toml::node& at, std::string_view key, const std::string& msg)> fail;
  // The path a `file` parameter names (the scene resolves it against the file it is written in
  // and checks that it exists). Default: as written.
  std::function<std::string(const toml::node& at, std::string_view key, const std::string& path)>
      file;
  // A nested table { type = "...", ... }: an origin function (ParamType::Function) or a texture
  // (ParamType::Texture); `spec` says which.
  std::function<std::shared_ptr<const NestedFunction>(const toml::table& t, const ParamSpec& spec)>
      nested;
};

// The value of `spec` written as `n`: type, range and choices checked.
ParamValue param_from_toml(const ParamSpec& spec, const toml::node& n, const ParamTomlHooks& hooks);

}  // namespace anamorph
