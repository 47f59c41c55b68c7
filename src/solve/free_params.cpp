#include "solve/free_params.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

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

// The number of array levels of a value of type `t` (0: a number), or -1 when it is not made of
// numbers.
int depth(ParamType t) {
  switch (t) {
    case ParamType::Number:
      return 0;
    case ParamType::Vec2:
    case ParamType::Vec3:
    case ParamType::NumberList:
      return 1;
    case ParamType::Vec3List:
    case ParamType::NumberGrid:
      return 2;
    case ParamType::Vec3Grid:
      return 3;
    default:
      return -1;
  }
}

// Appends the numbers of `node` (a number or nested arrays of them, as deep as `dims` is long,
// with these extents) to `v`. False when it is not of that form (ragged, or not numbers).
bool flatten(const toml::node& node, const std::vector<size_t>& dims, std::vector<double>& v,
             size_t level = 0) {
  if (level == dims.size()) {
    const std::optional<double> x = node.value<double>();
    if (x) v.push_back(*x);
    return x.has_value();
  }
  const toml::array* a = node.as_array();
  if (!a || a->size() != dims[level]) return false;
  for (const toml::node& e : *a)
    if (!flatten(e, dims, v, level + 1)) return false;
  return true;
}

// The extents of `node`'s first entries, `levels` deep (empty entries: false).
bool extents(const toml::node& node, int levels, std::vector<size_t>& dims) {
  const toml::node* n = &node;
  for (int l = 0; l < levels; ++l) {
    const toml::array* a = n->as_array();
    if (!a || a->empty()) return false;
    dims.push_back(a->size());
    n = a->get(0);
  }
  return true;
}

// The value of `key`: from the scene, else the declared default; empty when neither.
FreeValue start_value(const toml::table& scene, const std::string& key, const ParamSpec& spec) {
  const toml::node* node = at_path(scene, split(key));
  toml::table def;
  if (!node && spec.default_value != "none" && !spec.default_value.empty()) {
    def = parse_value_text(std::string(spec.default_value));
    node = def.get("v");
  }
  FreeValue f{key, {}, {}};
  if (!node || !extents(*node, depth(spec.type), f.dims) || !flatten(*node, f.dims, f.start))
    f.start.clear();
  return f;
}

// "1.2.0": the indices of flat component `i` of a value of extents `dims`.
std::string index_text(size_t i, const std::vector<size_t>& dims) {
  std::string t;
  for (size_t k = dims.size(); k-- > 0;) {
    t = fmt::format(".{}", i % dims[k]) + t;
    i /= dims[k];
  }
  return t;
}

// The value's numbers as TOML text, nested as `dims` says.
std::string nested_text(const std::vector<double>& v, const std::vector<size_t>& dims, size_t level,
                        size_t& at) {
  if (level == dims.size()) return fmt::format("{}", v[at++]);
  std::string t = "[";
  for (size_t i = 0; i < dims[level]; ++i)
    t += (i ? ", " : "") + nested_text(v, dims, level + 1, at);
  return t + "]";
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
    size_t at = 0;
    out.emplace_back(values[k].key, nested_text(v[k], values[k].dims, 0, at));
  }
  for (const DerivedValue& d : derived) {  // fov = 2 theta(1), degrees
    double theta1 = 0;
    for (double k : v[d.value]) theta1 += k;
    out.emplace_back(d.key, fmt::format("{}", 2 * theta1 * 180 / std::numbers::pi));
  }
  return out;
}

std::vector<std::string> FreeValues::overrides(const std::vector<double>& x) const {
  std::vector<std::string> o;
  for (const auto& [key, text] : texts(x)) o.push_back(key + "=" + text);
  return o;
}

namespace {

// The declaration of `parts` (a camera key, without "camera", possibly ending in indices into a
// list value); the indices are moved from `parts` to `index`.
const ParamSpec* resolve_key(const toml::table& scene, std::vector<std::string>& parts,
                             std::vector<size_t>& index) {
  const ParamSpec* spec = declaration(scene, parts);
  std::vector<size_t> reversed;
  while (!spec && parts.size() >= 2 && is_index(parts.back()) && reversed.size() < 3) {
    reversed.push_back(std::stoul(parts.back()));
    parts.pop_back();
    spec = declaration(scene, parts);
  }
  index.assign(reversed.rbegin(), reversed.rend());
  return spec;
}

// One scalar per component [first, first + count) of value `vi`, bounded by the declared range
// narrowed by the entry's min and max.
template <class Fail>
void add_scalars(FreeValues& out, size_t vi, size_t first, size_t count, const ParamSpec& spec,
                 const FreeKey& k, const Fail& fail) {
  const FreeValue& v = out.values[vi];
  const ParamSpec range = with_world_range(spec);
  for (size_t c = first; c < first + count; ++c) {
    for (const FreeScalar& s : out.scalars)
      if (s.value == vi && s.component == int(c)) fail("is already free (a key that holds it)");
    double lo = inside(range.min, range.min_exclusive, range.max);
    double hi = inside(range.max, range.max_exclusive, range.min);
    if (k.min) lo = std::max(lo, *k.min);
    if (k.max) hi = std::min(hi, *k.max);
    if (!(lo <= hi))
      fail(fmt::format("min and max leave no value in [{}, {}]", range.min, range.max));
    const double s0 = v.start[c];
    if (s0 < lo || s0 > hi)
      fail(fmt::format("its value {} lies outside the bounds [{}, {}]", s0, lo, hi));
    out.scalars.push_back({vi, int(c), v.key + index_text(c, v.dims), lo, hi, k.where});
  }
}

// A free `camera.poly` of a polynomial fisheye decides its fov (DerivedValue), which may then not
// be free itself.
void add_derived(FreeValues& out, const toml::table& scene, const std::string& file) {
  for (size_t vi = 0; vi < out.values.size(); ++vi) {
    if (out.values[vi].key != "camera.poly") continue;
    for (const FreeScalar& s : out.scalars)
      if (out.values[s.value].key == "camera.fov")
        throw SceneError({file, 0, 0}, s.where + ".key",
                         "\"camera.fov\" follows the free camera.poly (fov = 2 theta(1) = 2 (k0 + "
                         "k1 + ...)): free one or the other");
    if (string_at(scene, "camera.mapping", "") == "polynomial")
      out.derived.push_back({"camera.fov", vi});
  }
}

}  // namespace

FreeValues resolve_free(const std::vector<FreeKey>& keys, const toml::table& scene,
                        const std::vector<std::string>& animated, const std::string& file) {
  FreeValues out;
  for (const FreeKey& k : keys) {
    const auto fail = [&](const std::string& msg) {
      throw SceneError({file, 0, 0}, k.where + ".key", fmt::format("\"{}\": {}", k.key, msg));
    };
    std::vector<std::string> parts = split(k.key);
    parts.erase(parts.begin());  // "camera"
    std::vector<size_t> index;
    const ParamSpec* spec = resolve_key(scene, parts, index);
    if (!spec) fail("not a declared key of this camera");
    if (depth(spec->type) < 0 || int(index.size()) > depth(spec->type))
      fail(fmt::format("a {}: only numbers and lists of numbers can be solved for",
                       to_string(spec->type)));
    std::string value_key = "camera";
    for (const std::string& p : parts) value_key += "." + p;
    for (const std::string& a : animated)
      if (a == value_key || k.key.starts_with(a + ".") || a.starts_with(value_key + "."))
        fail(
            "has [[animate]] keys: a free key cannot be animated (solve --frames writes its keys; "
            "solve the scene without them)");
    size_t vi = 0;
    while (vi < out.values.size() && out.values[vi].key != value_key) ++vi;
    if (vi == out.values.size()) {
      FreeValue v = start_value(scene, value_key, *spec);
      if (v.start.empty()) fail("has no value to start from: give it one in the scene");
      out.values.push_back(std::move(v));
    }
    const std::vector<size_t>& dims = out.values[vi].dims;
    // The block of components the indices select: [first, first + count).
    size_t first = 0, count = out.values[vi].start.size();
    for (size_t l = 0; l < index.size(); ++l) {
      if (index[l] >= dims[l])
        fail(fmt::format("index {} is out of range: that level has {} entries (0..{})", index[l],
                         dims[l], dims[l] - 1));
      count /= dims[l];
      first += index[l] * count;
    }
    add_scalars(out, vi, first, count, *spec, k, fail);
  }
  add_derived(out, scene, file);
  return out;
}

}  // namespace anamorph::solve
