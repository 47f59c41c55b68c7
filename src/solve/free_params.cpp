#include "solve/free_params.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "camera/coins.h"
#include "camera/functions.h"
#include "camera/presets.h"
#include "params/read_params.h"
#include "scene/scene_schema.h"
#include "scene/toml_edit.h"

namespace anamorph::solve {

namespace {

std::vector<std::string> split(const std::string& key) {
  std::vector<std::string> parts;
  size_t a = 0;
  for (size_t b; (b = key.find('.', a)) != std::string::npos; a = b + 1)
    parts.push_back(key.substr(a, b - a));
  parts.push_back(key.substr(a));
  return parts;
}

bool is_index(const std::string& s) {
  return !s.empty() && s.size() < 9 && std::all_of(s.begin(), s.end(), ::isdigit);
}

const toml::node* at_path(const toml::table& root, const std::vector<std::string>& parts) {
  const toml::node* n = &root;
  for (const std::string& p : parts) {
    if (const toml::table* t = n->as_table())
      n = t->get(p);
    else if (const toml::array* a = n->as_array(); a && is_index(p))
      n = a->get(size_t(std::stoul(p)));
    else
      return nullptr;
    if (!n) return nullptr;
  }
  return n;
}

std::string string_at(const toml::table& root, const std::string& key, std::string fallback) {
  const toml::node* n = at_path(root, split(key));
  return n && n->is_string() ? std::string(*n->value<std::string>()) : fallback;
}

// The declaration of the camera key `parts` (without its leading "camera"), or null.
const ParamSpec* declaration(const toml::table& scene, const std::vector<std::string>& parts) {
  if (parts.size() == 1) {
    if (parts[0] == "preset") return &camera_preset_spec();
    if (const ParamSpec* s = find_param({camera_common_params()}, parts[0])) return s;
    if (at_path(scene, {"camera", "org"}) || at_path(scene, {"camera", "dir"})) return nullptr;
    const PresetInfo* p = find_preset(string_at(scene, "camera.preset", "perspective"));
    return p ? find_param({p->params}, parts[0]) : nullptr;
  }
  if (parts.size() == 3 && parts[0] == "coin" && is_index(parts[1]))
    return find_param({coin_params()}, parts[2]);
  if (parts.size() == 2 && (parts[0] == "org" || parts[0] == "dir")) {
    const std::string type = string_at(scene, "camera." + parts[0] + ".type", "");
    if (parts[0] == "org") {
      const OrgFunctionInfo* f = find_org_function(type);
      return f ? find_param({f->params}, parts[1]) : nullptr;
    }
    const DirFunctionInfo* f = find_dir_function(type);
    return f ? find_param({f->params}, parts[1]) : nullptr;
  }
  return nullptr;
}

int components(ParamType t) {
  switch (t) {
    case ParamType::Number:
      return 1;
    case ParamType::Vec2:
      return 2;
    case ParamType::Vec3:
      return 3;
    default:
      return 0;
  }
}

// The value's components: from the scene, else the declared default.
std::vector<double> start_value(const toml::table& scene, const std::string& key,
                                const ParamSpec& spec, int n) {
  const toml::node* node = at_path(scene, split(key));
  toml::table def;
  if (!node && spec.default_value != "none" && !spec.default_value.empty()) {
    def = parse_value_text(std::string(spec.default_value));
    node = def.get("v");
  }
  if (!node) return {};
  std::vector<double> v;
  if (const toml::array* a = node->as_array()) {
    for (const toml::node& e : *a)
      if (auto x = e.value<double>()) v.push_back(*x);
  } else if (auto x = node->value<double>()) {
    v.push_back(*x);
  }
  if (int(v.size()) != n) return {};
  return v;
}

// Bounds strictly inside an exclusive end (the reader refuses the end itself).
double inside(double end, bool exclusive, double toward) {
  if (!exclusive || !std::isfinite(end)) return end;
  const double step = std::max(1e-9 * std::abs(end), 1e-12);
  return toward > end ? end + step : end - step;
}

}  // namespace

std::vector<double> FreeValues::start() const {
  std::vector<double> x;
  for (const FreeScalar& s : scalars) x.push_back(values[s.value].start[size_t(s.component)]);
  return x;
}

std::vector<std::pair<std::string, std::string>> FreeValues::texts(
    const std::vector<double>& x) const {
  std::vector<std::vector<double>> v;
  for (const FreeValue& f : values) v.push_back(f.start);
  for (size_t i = 0; i < scalars.size(); ++i)
    v[scalars[i].value][size_t(scalars[i].component)] = x[i];
  std::vector<std::pair<std::string, std::string>> out;
  for (size_t k = 0; k < values.size(); ++k) {
    std::string t;
    for (double c : v[k]) t += fmt::format("{}{}", t.empty() ? "" : ", ", c);
    out.emplace_back(values[k].key, values[k].vector ? "[" + t + "]" : t);
  }
  return out;
}

std::vector<std::string> FreeValues::overrides(const std::vector<double>& x) const {
  std::vector<std::string> o;
  for (const auto& [key, text] : texts(x)) o.push_back(key + "=" + text);
  return o;
}

FreeValues resolve_free(const std::vector<FreeKey>& keys, const toml::table& scene,
                        const std::vector<std::string>& animated, const std::string& file) {
  FreeValues out;
  for (const FreeKey& k : keys) {
    const auto fail = [&](const std::string& msg) {
      throw SceneError({file, 0, 0}, k.where + ".key", fmt::format("\"{}\": {}", k.key, msg));
    };
    std::vector<std::string> parts = split(k.key);
    parts.erase(parts.begin());  // "camera"
    int component = -1;
    const ParamSpec* spec = declaration(scene, parts);
    if (!spec && parts.size() >= 2 && is_index(parts.back())) {
      component = std::stoi(parts.back());
      parts.pop_back();
      spec = declaration(scene, parts);
    }
    if (!spec) fail("not a declared key of this camera");
    const int n = components(spec->type);
    if (n == 0 || (component >= 0 && n == 1))
      fail(fmt::format("a {}: only numbers and vectors of numbers can be solved for",
                       to_string(spec->type)));
    if (component >= n) fail(fmt::format("the key has {} components (0..{})", n, n - 1));
    std::string value_key = "camera";
    for (const std::string& p : parts) value_key += "." + p;
    for (const std::string& a : animated)
      if (a == value_key || k.key.starts_with(a + ".") || a.starts_with(value_key + "."))
        fail("has [[animate]] keys: solving an animated key is not supported yet");
    size_t vi = 0;
    while (vi < out.values.size() && out.values[vi].key != value_key) ++vi;
    if (vi == out.values.size()) {
      std::vector<double> start = start_value(scene, value_key, *spec, n);
      if (start.empty()) fail("has no value to start from: give it one in the scene");
      out.values.push_back({value_key, std::move(start), n > 1});
    }
    const ParamSpec range = with_world_range(*spec);
    for (int c = component < 0 ? 0 : component; c < (component < 0 ? n : component + 1); ++c) {
      for (const FreeScalar& s : out.scalars)
        if (s.value == vi && s.component == c) fail("is already free (a key that holds it)");
      double lo = inside(range.min, range.min_exclusive, range.max);
      double hi = inside(range.max, range.max_exclusive, range.min);
      if (k.min) lo = std::max(lo, *k.min);
      if (k.max) hi = std::min(hi, *k.max);
      if (!(lo <= hi))
        fail(fmt::format("min and max leave no value in [{}, {}]", range.min, range.max));
      const double s0 = out.values[vi].start[size_t(c)];
      if (s0 < lo || s0 > hi)
        fail(fmt::format("its value {} lies outside the bounds [{}, {}]", s0, lo, hi));
      out.scalars.push_back(
          {vi, c, n > 1 ? fmt::format("{}.{}", value_key, c) : value_key, lo, hi, k.where});
    }
  }
  return out;
}

}  // namespace anamorph::solve
