#include "params/read_params.h"

#include <fmt/format.h>

#include <cstdlib>
#include <string>
#include <unordered_map>
#include <vector>

namespace anamorph {

const ParamSpec* find_param(std::initializer_list<std::span<const ParamSpec>> groups,
                            std::string_view name) {
  for (const auto& g : groups)
    for (const ParamSpec& s : g)
      if (s.name == name) return &s;
  return nullptr;
}

namespace {

// A default's TOML text parsed, once per text and thread (the solver builds a camera, and so reads
// its defaults, hundreds of times a second).
const toml::node& parsed_default(const ParamSpec& spec) {
  thread_local std::unordered_map<std::string, toml::table> cache;
  const std::string text(spec.default_value);
  auto it = cache.find(text);
  if (it == cache.end()) {
    if (cache.size() > 4096) cache.clear();  // (defaults of generated specs could be many)
    it = cache.emplace(text, toml::parse("v = " + text)).first;
  }
  return *it->second.get("v");
}

}  // namespace

ParamValues read_params(const toml::table& t,
                        std::initializer_list<std::span<const ParamSpec>> groups,
                        const ParamWalk& walk) {
  const ParamTomlHooks& h = walk.hooks;
  ParamValues out;
  for (const auto& g : groups)
    for (const ParamSpec& spec : g) {
      if (const toml::node* n = t.get(spec.name)) {
        out.set(std::string(spec.name), param_from_toml(spec, *n, h));
      } else if (spec.default_value.empty()) {
        h.fail(t, spec.name, "is required");
        std::abort();  // (fail hooks throw)
      } else if (spec.default_value != "none") {
        out.set(std::string(spec.name), param_from_toml(spec, parsed_default(spec), h));
      }
    }
  for (const auto& [k, v] : t) {
    const std::string_view key = k.str();
    if (find_param(groups, key)) continue;
    bool also = false;
    for (std::string_view a : walk.also) also |= a == key;
    if (also) continue;
    std::vector<std::string> known;
    for (const auto& g : groups)
      for (const ParamSpec& s : g) known.emplace_back(s.name);
    for (std::string_view a : walk.also) known.emplace_back(a);
    const std::string s = suggest(key, known);
    std::string msg = "unknown key";
    if (!s.empty()) {
      msg += fmt::format(" (did you mean '{}'?)", s);
    } else if (!known.empty()) {
      msg += " (valid keys here: ";
      for (size_t i = 0; i < known.size(); ++i) msg += (i ? ", " : "") + known[i];
      msg += ")";
    }
    if (walk.unknown_key) walk.unknown_key(k, msg);
    h.fail(v, key, msg);
    std::abort();
  }
  return out;
}

}  // namespace anamorph
