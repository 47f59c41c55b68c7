// The one walker over a TOML table by its declared parameters: every key of a scene enters the
// program here (or through param_from_toml for a single value). Types, ranges and choices are
// checked by the spec, absent keys take their defaults, required ones are reported, and a key
// that no spec names is rejected with the closest known key as a suggestion.
#pragma once

#include <initializer_list>
#include <span>
#include <string_view>

#include <toml++/toml.h>

#include "params/param_toml.h"
#include "params/params.h"

namespace anamorph {

struct ParamWalk {
  ParamTomlHooks hooks;  // hooks.fail reports bad and missing values (missing: `at` = the table)
  // Reports a key no spec names (at the key's own position); must throw. Default: hooks.fail at
  // the value.
  std::function<void(const toml::key& k, const std::string& msg)> unknown_key;
  // Keys the caller reads itself (e.g. a selector such as `type`, or a sub-table): accepted.
  std::span<const std::string_view> also = {};
};

// Reads every spec of `groups` (e.g. a table's common keys and its type's own) from t.
ParamValues read_params(const toml::table& t,
                        std::initializer_list<std::span<const ParamSpec>> groups,
                        const ParamWalk& walk);

// The spec named `name` in groups, or null.
const ParamSpec* find_param(std::initializer_list<std::span<const ParamSpec>> groups,
                            std::string_view name);

}  // namespace anamorph
