#include "params/param_toml.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <vector>

#include <fmt/format.h>

#include "math/user_text.h"

namespace anamorph {

std::optional<double> toml_number(const toml::node& n) {
  if (auto v = n.value<double>()) return *v;
  return std::nullopt;
}

std::optional<int64_t> toml_integer(const toml::node& n) {
  if (n.is_integer()) return n.value<int64_t>();
  if (auto d = n.value<double>();
      d && std::isfinite(*d) && *d == std::round(*d) && std::abs(*d) < 9e15)
    return int64_t(*d);
  return std::nullopt;
}

std::string toml_type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::table:
      return "a table";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a number";
    case toml::node_type::boolean:
      return "a boolean";
    default:
      return "a date/time";
  }
}

std::string range_error(double v, double lo_bound, double hi_bound, bool lo_ex, bool hi_ex) {
  if (!std::isfinite(v)) return fmt::format("must be a finite number, got {}", v);
  const bool below = lo_ex ? !(v > lo_bound) : !(v >= lo_bound);
  const bool above = hi_ex ? !(v < hi_bound) : !(v <= hi_bound);
  if (!below && !above) return "";
  // (Bounds as written in the docs: 1e+12 rather than 1000000000000.)
  const auto text = [](double x) {
    return std::abs(x) >= 1e9 ? fmt::format("{:.10g}", x) : fmt::format("{}", x);
  };
  const std::string lo = text(lo_bound), hi = text(hi_bound);
  std::string range = fmt::format("{}{}, {}{}", lo_ex ? "(" : "[", lo, hi, hi_ex ? ")" : "]");
  if (std::isinf(hi_bound))
    range = fmt::format("{} {}", lo_ex ? ">" : ">=", lo);
  else if (std::isinf(lo_bound))
    range = fmt::format("{} {}", hi_ex ? "<" : "<=", hi);
  return fmt::format("value {} is out of range (must be {})", v, range);
}

namespace {

size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] != b[j - 1])});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

}  // namespace

std::string suggest(std::string_view word, std::span<const std::string> candidates) {
  std::string best;
  size_t best_d = std::max<size_t>(2, word.size() / 3) + 1;
  for (const auto& c : candidates) {
    const size_t d = edit_distance(word, c);
    if (d < best_d) best_d = d, best = c;
  }
  return best;
}

std::string join_choices(std::span<const std::string_view> c) {
  std::string s;
  for (size_t i = 0; i < c.size(); ++i)
    s += (i ? ", " : "") + std::string("\"") + std::string(c[i]) + "\"";
  return s;
}

namespace {

// A transform table { matrix, scale, rotate, translate }, applied to points as T * R * S * M.
// Errors name the sub-key from the outer key ("transform.scale"). One method a sub-key.
class TransformReader {
 public:
  TransformReader(const ParamSpec& spec, const ParamTomlHooks& h) : outer_(spec.name), h_(h) {}

  Transform read(const toml::node& n) const {
    const toml::table* t = n.as_table();
    if (!t)
      fail(n, "",
           "expected a table { translate = [...], rotate = [deg, x, y, z], scale = ..., matrix = "
           "[16 numbers] }");
    static const std::string kKeys[] = {"matrix", "rotate", "scale", "translate"};
    for (const auto& [k, v] : *t)
      if (std::find(std::begin(kKeys), std::end(kKeys), k.str()) == std::end(kKeys)) {
        const std::string s = suggest(k.str(), kKeys);
        fail(v, k.str(),
             s.empty() ? "unknown key (valid keys here: matrix, rotate, scale, translate)"
                       : fmt::format("unknown key (did you mean '{}'?)", s));
      }
    Transform m, s, rot, tr;
    if (const toml::node* mn = t->get("matrix")) m = matrix(*mn);
    if (const toml::node* sn = t->get("scale")) s = scale(*sn);
    if (const toml::node* rn = t->get("rotate")) rot = rotate(*rn);
    if (const toml::node* tn = t->get("translate")) tr = translate(*tn);
    return tr * rot * s * m;
  }

 private:
  [[noreturn]] void fail(const toml::node& at, std::string_view sub, const std::string& msg) const {
    h_.fail(at, sub.empty() ? outer_ : outer_ + "." + std::string(sub), msg);
    std::abort();  // (fail hooks throw)
  }

  // (Every number of a transform within the world's range: products of a few of them still
  // are, and placement_error checks what they compose to.)
  double finite(const toml::node& x, std::string_view sub, const char* what) const {
    const auto v = toml_number(x);
    if (!v || !std::isfinite(*v)) fail(x, sub, what);
    if (!(std::abs(*v) <= kMaxCoordinate))
      fail(x, sub, range_error(*v, -kMaxCoordinate, kMaxCoordinate));
    return *v;
  }

  Transform matrix(const toml::node& mn) const {
    const toml::array* a = mn.as_array();
    if (!a || a->size() != 16) fail(mn, "matrix", "expected 16 numbers (row-major 4x4)");
    Mat4 mat;
    for (int i = 0; i < 16; ++i)
      mat.m[i / 4][i % 4] = finite(*a->get(size_t(i)), "matrix", "expected 16 finite numbers");
    bool ok = false;
    const Mat4 inv = inverse(mat, &ok);
    if (!ok) fail(mn, "matrix", "matrix is singular");
    return Transform(mat, inv);
  }

  Transform scale(const toml::node& sn) const {
    Vec3 sv;
    if (const auto x = toml_number(sn)) {
      sv = Vec3(*x);
    } else {
      const toml::array* a = sn.as_array();
      if (!a || a->size() != 3) fail(sn, "scale", "expected a number or [sx, sy, sz]");
      for (int i = 0; i < 3; ++i) {
        const auto x3 = toml_number(*a->get(size_t(i)));
        if (!x3) fail(sn, "scale", "expected a number or [sx, sy, sz]");
        sv[i] = *x3;
      }
    }
    if (!is_finite(sv) || sv.x == 0 || sv.y == 0 || sv.z == 0)
      fail(sn, "scale", "scale factors must be finite and non-zero");
    if (!within_world(sv))
      fail(sn, "scale",
           range_error(max_component(Vec3{std::abs(sv.x), std::abs(sv.y), std::abs(sv.z)}),
                       -kMaxCoordinate, kMaxCoordinate));
    return Transform::scale(sv);
  }

  // [deg, ax, ay, az] or a list of them, applied in order.
  Transform rotate(const toml::node& rn) const {
    const auto one = [&](const toml::array& a) {
      if (a.size() != 4) fail(rn, "rotate", "expected [degrees, axis_x, axis_y, axis_z]");
      double v[4];
      for (int i = 0; i < 4; ++i)
        v[i] = finite(*a.get(size_t(i)), "rotate", "expected 4 finite numbers");
      if (Vec3{v[1], v[2], v[3]} == Vec3{0, 0, 0})
        fail(rn, "rotate", "rotation axis must not be zero");
      return Transform::rotate(v[0], {v[1], v[2], v[3]});
    };
    const toml::array* a = rn.as_array();
    if (!a || a->empty()) fail(rn, "rotate", "expected [degrees, x, y, z] or a list of them");
    if (!a->get(0)->is_array()) return one(*a);
    Transform rot;
    for (const auto& e : *a) {
      if (!e.is_array()) fail(rn, "rotate", "expected a list of [degrees, x, y, z]");
      rot = one(*e.as_array()) * rot;
    }
    return rot;
  }

  Transform translate(const toml::node& tn) const {
    const toml::array* a = tn.as_array();
    if (!a || a->size() != 3)
      fail(tn, "translate", "expected an array of 3 numbers [x, y, z], got " + toml_type_name(tn));
    Vec3 v;
    for (int i = 0; i < 3; ++i)
      v[i] = finite(*a->get(size_t(i)), "translate", "components must be finite numbers");
    return Transform::translate(v);
  }

  const std::string outer_;
  const ParamTomlHooks& h_;
};

Transform transform_from_toml(const ParamSpec& spec, const toml::node& n, const ParamTomlHooks& h) {
  return TransformReader(spec, h).read(n);
}

// A number where an integer key wants one, and toml_integer did not take it: not finite, or
// whole but beyond the exact integers of a double (an integer too large for TOML's 64 bits, such
// as Python's 2**70, arrives so). Says that it is out of the key's range, or out of reach; a
// fraction is left to the caller ("expected an integer").
template <class Fail>
void integer_out_of_reach(const toml::node& n, const ParamSpec& spec, const Fail& fail) {
  const double d = *n.value<double>();
  if (std::isfinite(d) && d != std::round(d)) return;
  const std::string e = range_error(d, spec.min, spec.max, spec.min_exclusive, spec.max_exclusive);
  fail(n, !e.empty() ? e
                     : fmt::format("value {} is out of range (must be an integer; as a number at "
                                   "most 9e15 in size, written as an integer up to 2^63 - 1)",
                                   d));
}

}  // namespace

namespace {

// One value's reading against its declaration: the checks every type shares (hooks' fail throws).
struct ValueReader {
  const ParamSpec spec;
  const ParamTomlHooks& h;

  [[noreturn]] void fail(const toml::node& at, const std::string& msg) const {
    h.fail(at, spec.name, msg);
    std::abort();  // (fail hooks throw)
  }
  void in_range(const toml::node& at, double v) const {
    const std::string e =
        range_error(v, spec.min, spec.max, spec.min_exclusive, spec.max_exclusive);
    if (!e.empty()) fail(at, e);
  }
  double num(const toml::node& x) const {
    const auto v = toml_number(x);
    if (!v) fail(x, "expected a number, got " + toml_type_name(x));
    in_range(x, *v);
    return *v;
  }
  Vec3 vec(const toml::node& x, size_t dim) const {
    const toml::array* a = x.as_array();
    if (!a || a->size() != dim)
      fail(x, fmt::format("expected an array of {} numbers, got {}", dim, toml_type_name(x)));
    Vec3 v;
    for (size_t i = 0; i < dim; ++i) v[int(i)] = num(*a->get(i));
    return v;
  }
  Vec3 color(const toml::node& x) const {
    if (const auto g = toml_number(x)) {
      in_range(x, *g);
      return Vec3(*g);
    }
    const toml::array* a = x.as_array();
    if (!a || a->size() != 3)
      fail(x, "expected a colour [r, g, b] or a number, got " + toml_type_name(x));
    return vec(x, 3);
  }
  const toml::array& list(const toml::node& x) const {
    const toml::array* a = x.as_array();
    if (!a) fail(x, "expected an array, got " + toml_type_name(x));
    return *a;
  }
  ParamValue integer(const toml::node& n) const {
    const auto v = toml_integer(n);
    const auto failer = [this](const toml::node& at, const std::string& msg) { fail(at, msg); };
    if (!v && n.is_floating_point()) integer_out_of_reach(n, spec, failer);
    if (!v) fail(n, "expected an integer, got " + toml_type_name(n));
    in_range(n, double(*v));
    return *v;
  }
  ParamValue string(const toml::node& n) const {
    const std::string_view key = spec.name;
    if (!n.is_string()) fail(n, "expected a string, got " + toml_type_name(n));
    std::string v = *n.value<std::string>();
    if (!spec.choices.empty() &&
        std::find(spec.choices.begin(), spec.choices.end(), v) == spec.choices.end()) {
      std::vector<std::string> cs(spec.choices.begin(), spec.choices.end());
      const std::string s = suggest(v, cs);
      fail(n, fmt::format("unknown value \"{}\"{} (valid: {})", v,
                          s.empty() ? "" : fmt::format(" (did you mean \"{}\"?)", s),
                          join_choices(spec.choices)));
    }
    // A NUL would cut the name short where the system reads it: refused, with or without hooks.
    if (key == "file" && has_nul(v)) fail(n, nul_in_path_message(v));
    if (key == "file" && h.file) return h.file(n, key, v);
    return v;
  }
  // An array of arrays, each element read by `one`.
  template <class T, class F>
  std::vector<std::vector<T>> grid(const toml::node& n, F one) const {
    std::vector<std::vector<T>> out;
    for (const auto& row : list(n)) {
      out.emplace_back();
      for (const auto& e : list(row)) out.back().push_back(one(e));
    }
    return out;
  }
  ParamValue string_map(const toml::node& n) const {
    const toml::table* t = n.as_table();
    if (!t) fail(n, "expected a table { name = number, ... }");
    std::map<std::string, double> out;
    for (const auto& [k, v] : *t) {
      const auto x = toml_number(v);
      if (!x || !std::isfinite(*x))
        fail(v, fmt::format("constant '{}' must be a finite number", k.str()));
      out[std::string(k.str())] = *x;
    }
    return out;
  }
};

}  // namespace

// (A switch over the closed set of parameter types.)
ParamValue param_from_toml(const ParamSpec& declared, const toml::node& n,
                           const ParamTomlHooks& h) {
  const ValueReader r{with_world_range(declared), h};
  const auto num = [&](const toml::node& x) { return r.num(x); };
  const auto vec3 = [&](const toml::node& x) { return r.vec(x, 3); };
  switch (r.spec.type) {
    case ParamType::Number:
      return r.num(n);
    case ParamType::Integer:
      return r.integer(n);
    case ParamType::Bool:
      if (!n.is_boolean()) r.fail(n, "expected true or false, got " + toml_type_name(n));
      return *n.value<bool>();
    case ParamType::String:
      return r.string(n);
    case ParamType::Vec2: {
      const Vec3 v = r.vec(n, 2);
      return Vec2{v.x, v.y};
    }
    case ParamType::Vec3:
      return r.vec(n, 3);
    case ParamType::NumberList: {
      std::vector<double> out;
      for (const auto& e : r.list(n)) out.push_back(r.num(e));
      return out;
    }
    case ParamType::Vec3List: {
      std::vector<Vec3> out;
      for (const auto& e : r.list(n)) out.push_back(r.vec(e, 3));
      return out;
    }
    case ParamType::Vec3Grid:
      return r.grid<Vec3>(n, vec3);
    case ParamType::NumberGrid:
      return r.grid<double>(n, num);
    case ParamType::StringMap:
      return r.string_map(n);
    case ParamType::Function: {
      const toml::table* t = n.as_table();
      if (!t) r.fail(n, "expected a table { type = \"...\", ... }");
      return h.nested(*t, r.spec);
    }
    case ParamType::Color:
      return r.color(n);
    case ParamType::Texture:
      if (const toml::table* t = n.as_table()) return h.nested(*t, r.spec);
      return r.color(n);
    case ParamType::Transform:
      return transform_from_toml(r.spec, n, h);
  }
  r.fail(n, "unsupported parameter type");
}

}  // namespace anamorph
