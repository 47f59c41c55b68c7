#include "scene/animation.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "scene/scene_schema.h"

namespace anamorph {

namespace {

// [[animate]]'s declared keys but `keys`, whose [frame, value] pairs are read below.
std::vector<ParamSpec> walked_keys() {
  std::vector<ParamSpec> specs;
  for (const ParamSpec& s : animate_schema().common)
    if (s.name != "keys") specs.push_back(s);
  return specs;
}

// Flattens a number or nested array of numbers; false if anything else appears.
bool flatten(const toml::node& n, std::vector<double>* out) {
  if (auto v = n.value<double>()) {
    if (!std::isfinite(*v)) return false;
    out->push_back(*v);
    return true;
  }
  const toml::array* a = n.as_array();
  if (!a) return false;
  for (const auto& e : *a)
    if (!flatten(e, out)) return false;
  return true;
}

// Rebuilds a node of `shape`'s structure from consecutive values.
void rebuild(const toml::node& shape, const std::vector<double>& v, size_t* i, toml::array* out) {
  if (const toml::array* a = shape.as_array()) {
    toml::array sub;
    for (const auto& e : *a) rebuild(e, v, i, &sub);
    out->push_back(std::move(sub));
  } else {
    out->push_back(v[(*i)++]);
  }
}

}  // namespace

std::vector<AnimatedKey> take_animation(toml::table& root) {
  std::vector<AnimatedKey> out;
  toml::node* n = root.get("animate");
  if (!n) return out;
  const TableReader top(root, "");
  if (!n->is_array_of_tables()) top.fail("animate", "expected [[animate]] entries");
  int idx = 0;
  for (const auto& e : *n->as_array()) {
    const TableReader r(*e.as_table(), fmt::format("animate[{}]", idx++));
    if (!r.has("key"))
      r.fail("key", "is required: the dotted scene key to animate, e.g. \"camera.fov\"");
    static const std::vector<ParamSpec> specs = walked_keys();
    static constexpr std::string_view kKeys[] = {"keys"};
    const ParamValues v = r.params({specs}, kKeys);
    AnimatedKey a;
    a.key = v.string("key");
    if (a.key.empty())
      r.fail("key", "is required: the dotted scene key to animate, e.g. \"camera.fov\"");
    const std::string& interp = v.string("interpolation");
    a.interp = interp == "smooth"
                   ? AnimatedKey::Interp::Smooth
                   : (interp == "step" ? AnimatedKey::Interp::Step : AnimatedKey::Interp::Linear);
    a.loc = loc_of(*r.table().get("key"));
    const toml::node* keys = r.node("keys");
    if (!keys || !keys->is_array() || keys->as_array()->empty())
      r.fail("keys", "expected a list of [frame, value] pairs, e.g. [[0, 0.0], [59, 1.0]]");
    for (const auto& k : *keys->as_array()) {
      const toml::array* pair = k.as_array();
      if (!pair || pair->size() != 2 || !pair->get(0)->value<double>())
        r.fail_at(k, "keys", "each key is [frame, value] with a numeric frame");
      const double f = *pair->get(0)->value<double>();
      if (!a.frames.empty() && !(f > a.frames.back()))
        r.fail_at(k, "keys", "frames must increase strictly");
      std::vector<double> vals;
      if (!flatten(*pair->get(1), &vals))
        r.fail_at(k, "keys", "values must be finite numbers or arrays of numbers");
      toml::array wrap;
      wrap.push_back(*pair->get(1));
      a.raw.push_back(wrap);
      if (a.values.empty()) {
        a.shape = wrap;
      } else if (vals.size() != a.values.front().size()) {
        r.fail_at(k, "keys", "every key needs a value of the same shape");
      }
      a.frames.push_back(f);
      a.values.push_back(std::move(vals));
    }
    out.push_back(std::move(a));
  }
  root.erase("animate");
  return out;
}

std::vector<double> evaluate(const AnimatedKey& a, double f) {
  const size_t n = a.frames.size();
  if (n == 1 || f <= a.frames.front()) return a.values.front();
  if (f >= a.frames.back()) return a.values.back();
  const size_t i =
      size_t(std::upper_bound(a.frames.begin(), a.frames.end(), f) - a.frames.begin()) - 1;
  const double f0 = a.frames[i], f1 = a.frames[i + 1];
  const double t = (f - f0) / (f1 - f0);
  std::vector<double> out(a.values[i].size());
  for (size_t c = 0; c < out.size(); ++c) {
    const double p0 = a.values[i][c], p1 = a.values[i + 1][c];
    if (a.interp == AnimatedKey::Interp::Step) {
      out[c] = p0;
      continue;
    }
    if (a.interp == AnimatedKey::Interp::Linear) {
      out[c] = p0 + (p1 - p0) * t;
      continue;
    }
    // Cubic Hermite with Catmull-Rom tangents (per unit frame), one-sided at the ends: C1 and
    // exact at every key.
    const double m0 =
        i > 0 ? (p1 - a.values[i - 1][c]) / (f1 - a.frames[i - 1]) : (p1 - p0) / (f1 - f0);
    const double m1 =
        i + 2 < n ? (a.values[i + 2][c] - p0) / (a.frames[i + 2] - f0) : (p1 - p0) / (f1 - f0);
    const double t2 = t * t, t3 = t2 * t, h = f1 - f0;
    out[c] = (2 * t3 - 3 * t2 + 1) * p0 + (t3 - 2 * t2 + t) * h * m0 + (-2 * t3 + 3 * t2) * p1 +
             (t3 - t2) * h * m1;
  }
  return out;
}

toml::table value_node(const AnimatedKey& a, double f) {
  toml::table t;
  if (a.interp == AnimatedKey::Interp::Step) {
    // The last key at or before f, exactly as written (integers stay integers).
    size_t i = 0;
    while (i + 1 < a.frames.size() && a.frames[i + 1] <= f) ++i;
    t.insert("v", *a.raw[i].get(0));
    return t;
  }
  const std::vector<double> v = evaluate(a, f);
  toml::array wrapped;
  size_t i = 0;
  rebuild(*a.shape.get(0), v, &i, &wrapped);
  t.insert("v", *wrapped.get(0));
  return t;
}

namespace {

// A dotted key as errors name it ("object[0].radius") in the form keys are set ("object.0.radius").
std::string dotted(std::string key) {
  for (char& c : key)
    if (c == '[' || c == ']') c = c == '[' ? '.' : '\0';
  std::erase(key, '\0');
  return key;
}

// Whether setting key `set` set (or replaced) the value of key `at`, or of a table around it.
bool sets(const std::string& set, const std::string& at) {
  return at == set || at.starts_with(set + ".");
}

}  // namespace

SceneError at_animate_entry(const SceneError& e, const std::vector<AnimatedKey>& animation,
                            const std::vector<std::string>& overrides, double frame) {
  if (!e.loc.file.empty() || e.key.empty()) return e;
  const std::string at = dotted(e.key);
  for (const std::string& o : overrides)
    if (sets(o.substr(0, o.find('=')), at)) return e;  // (--set wins over [[animate]])
  // The last entry for the key wins, as it was set last.
  for (auto a = animation.rbegin(); a != animation.rend(); ++a)
    if (sets(a->key, at))
      return SceneError(
          a->loc, e.key,
          fmt::format("{} (at frame {}, the value of this [[animate]] entry)", e.message, frame));
  return e;
}

}  // namespace anamorph
