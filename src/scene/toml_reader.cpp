#include "scene/toml_reader.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include <fmt/format.h>

#include "camera/functions.h"

namespace anamorph {

SceneError::SceneError(const SourceLoc& l, std::string k, const std::string& msg)
    : std::runtime_error([&] {
        std::string where = l.file.empty() ? std::string("--set") : l.file;
        if (l.line > 0) where += fmt::format(":{}:{}", l.line, l.column);
        return k.empty() ? fmt::format("{}: {}", where, msg)
                         : fmt::format("{}: {}: {}", where, k, msg);
      }()),
      loc(l),
      key(std::move(k)) {}

SourceLoc loc_of(const toml::node& n) {
  const auto& s = n.source();
  SourceLoc l;
  if (s.path) l.file = *s.path;
  l.line = int(s.begin.line);
  l.column = int(s.begin.column);
  return l;
}

SourceLoc loc_of(const toml::key& k) {
  const auto& s = k.source();
  SourceLoc l;
  if (s.path) l.file = *s.path;
  l.line = int(s.begin.line);
  l.column = int(s.begin.column);
  return l;
}

static size_t edit_distance(std::string_view a, std::string_view b) {
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

std::string suggest(std::string_view word, std::span<const std::string> candidates) {
  std::string best;
  size_t best_d = std::max<size_t>(2, word.size() / 3) + 1;
  for (const auto& c : candidates) {
    const size_t d = edit_distance(word, c);
    if (d < best_d) best_d = d, best = c;
  }
  return best;
}

TableReader::TableReader(const toml::table& t, std::string path) : t_(t), path_(std::move(path)) {}

std::string TableReader::full_key(std::string_view key) const {
  return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
}

void TableReader::mark(std::string_view key) {
  used_.insert(std::string(key));
  known_.insert(std::string(key));
}

const toml::node* TableReader::node(std::string_view key) {
  mark(key);
  return t_.get(key);
}

void TableReader::fail(std::string_view key, const std::string& msg) const {
  if (const toml::node* n = t_.get(key)) throw SceneError(loc_of(*n), full_key(key), msg);
  throw SceneError(loc_of(t_), full_key(key), msg);
}

void TableReader::fail_at(const toml::node& n, std::string_view key, const std::string& msg) const {
  throw SceneError(loc_of(n), full_key(key), msg);
}

static std::string type_name(const toml::node& n) {
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

static std::optional<double> as_number(const toml::node& n) {
  if (auto v = n.value<double>()) return *v;
  return std::nullopt;
}

static void check_range(const TableReader& r, const toml::node& n, std::string_view key, double v,
                        double lo, double hi, bool lo_ex = false, bool hi_ex = false) {
  if (!std::isfinite(v)) r.fail_at(n, key, fmt::format("must be a finite number, got {}", v));
  const bool below = lo_ex ? !(v > lo) : !(v >= lo);
  const bool above = hi_ex ? !(v < hi) : !(v <= hi);
  if (below || above) {
    std::string range = fmt::format("{}{}, {}{}", lo_ex ? "(" : "[", lo, hi, hi_ex ? ")" : "]");
    if (std::isinf(hi))
      range = fmt::format("{} {}", lo_ex ? ">" : ">=", lo);
    else if (std::isinf(lo))
      range = fmt::format("{} {}", hi_ex ? "<" : "<=", hi);
    r.fail_at(n, key, fmt::format("value {} is out of range (must be {})", v, range));
  }
}

double TableReader::number(std::string_view key, double def, double lo, double hi) {
  const toml::node* n = node(key);
  if (!n) return def;
  auto v = as_number(*n);
  if (!v) fail(key, "expected a number, got " + type_name(*n));
  check_range(*this, *n, key, *v, lo, hi);
  return *v;
}

double TableReader::required_number(std::string_view key, double lo, double hi) {
  if (!has(key)) fail(key, "is required");
  return number(key, 0, lo, hi);
}

// Integers, and floats with an integral value (animated keys interpolate as floats).
static std::optional<int64_t> as_integer(const toml::node& n) {
  if (n.is_integer()) return n.value<int64_t>();
  if (auto d = n.value<double>();
      d && std::isfinite(*d) && *d == std::round(*d) && std::abs(*d) < 9e15)
    return int64_t(*d);
  return std::nullopt;
}

int64_t TableReader::integer(std::string_view key, int64_t def, int64_t lo, int64_t hi) {
  const toml::node* n = node(key);
  if (!n) return def;
  auto v = as_integer(*n);
  if (!v) fail(key, "expected an integer, got " + type_name(*n));
  check_range(*this, *n, key, double(*v), double(lo), double(hi));
  return *v;
}

bool TableReader::boolean(std::string_view key, bool def) {
  const toml::node* n = node(key);
  if (!n) return def;
  if (!n->is_boolean()) fail(key, "expected true or false, got " + type_name(*n));
  return *n->value<bool>();
}

static std::string join_choices(std::span<const std::string_view> c) {
  std::string s;
  for (size_t i = 0; i < c.size(); ++i)
    s += (i ? ", " : "") + std::string("\"") + std::string(c[i]) + "\"";
  return s;
}

std::string TableReader::string(std::string_view key, std::string def,
                                std::span<const std::string_view> choices) {
  const toml::node* n = node(key);
  if (!n) return def;
  if (!n->is_string()) fail(key, "expected a string, got " + type_name(*n));
  std::string v = *n->value<std::string>();
  if (!choices.empty() && std::find(choices.begin(), choices.end(), v) == choices.end()) {
    std::vector<std::string> cs(choices.begin(), choices.end());
    const std::string s = suggest(v, cs);
    fail(key, fmt::format("unknown value \"{}\"{} (valid: {})", v,
                          s.empty() ? "" : fmt::format(" (did you mean \"{}\"?)", s),
                          join_choices(choices)));
  }
  return v;
}

static std::optional<Vec3> as_vec3(const toml::node& n) {
  const toml::array* a = n.as_array();
  if (!a || a->size() != 3) return std::nullopt;
  Vec3 v;
  for (int i = 0; i < 3; ++i) {
    auto x = as_number(*a->get(size_t(i)));
    if (!x) return std::nullopt;
    v[i] = *x;
  }
  return v;
}

static void check_finite_vec(const TableReader& r, const toml::node& n, std::string_view key,
                             const Vec3& v) {
  if (!is_finite(v)) r.fail_at(n, key, "components must be finite numbers");
}

std::optional<Vec3> TableReader::optional_vec3(std::string_view key) {
  const toml::node* n = node(key);
  if (!n) return std::nullopt;
  auto v = as_vec3(*n);
  if (!v) fail(key, "expected an array of 3 numbers [x, y, z], got " + type_name(*n));
  check_finite_vec(*this, *n, key, *v);
  return v;
}

Vec3 TableReader::vec3(std::string_view key, Vec3 def) { return optional_vec3(key).value_or(def); }

Color TableReader::color(std::string_view key, Color def) {
  const toml::node* n = node(key);
  if (!n) return def;
  if (auto x = as_number(*n)) {
    check_range(*this, *n, key, *x, 0, kInf);
    return Color(*x);
  }
  auto v = as_vec3(*n);
  if (!v) fail(key, "expected a colour [r, g, b] or a number, got " + type_name(*n));
  for (int i = 0; i < 3; ++i) check_range(*this, *n, key, (*v)[i], 0, kInf);
  return *v;
}

Transform TableReader::transform(std::string_view key) {
  const toml::node* n = node(key);
  if (!n) return {};
  const toml::table* t = n->as_table();
  if (!t)
    fail(key,
         "expected a table { translate = [...], rotate = [deg, x, y, z], scale = ..., matrix = [16 "
         "numbers] }");
  TableReader r(*t, full_key(key));
  Transform m;
  if (const toml::node* mn = r.node("matrix")) {
    const toml::array* a = mn->as_array();
    if (!a || a->size() != 16) r.fail("matrix", "expected 16 numbers (row-major 4x4)");
    Mat4 mat;
    for (int i = 0; i < 16; ++i) {
      auto x = as_number(*a->get(size_t(i)));
      if (!x || !std::isfinite(*x)) r.fail("matrix", "expected 16 finite numbers");
      mat.m[i / 4][i % 4] = *x;
    }
    bool ok = false;
    Mat4 inv = inverse(mat, &ok);
    if (!ok) r.fail("matrix", "matrix is singular");
    m = Transform(mat, inv);
  }
  // Applied to points in the order scale, rotate, translate (T * R * S).
  Transform s, rot, tr;
  if (const toml::node* sn = r.node("scale")) {
    Vec3 sv;
    if (auto x = as_number(*sn))
      sv = Vec3(*x);
    else if (auto v = as_vec3(*sn))
      sv = *v;
    else
      r.fail("scale", "expected a number or [sx, sy, sz]");
    if (!is_finite(sv) || sv.x == 0 || sv.y == 0 || sv.z == 0)
      r.fail("scale", "scale factors must be finite and non-zero");
    s = Transform::scale(sv);
  }
  if (const toml::node* rn = r.node("rotate")) {
    // [deg, ax, ay, az] or a list of them, applied in order.
    auto one = [&](const toml::array& a) {
      if (a.size() != 4) r.fail("rotate", "expected [degrees, axis_x, axis_y, axis_z]");
      double v[4];
      for (int i = 0; i < 4; ++i) {
        auto x = as_number(*a.get(size_t(i)));
        if (!x || !std::isfinite(*x)) r.fail("rotate", "expected 4 finite numbers");
        v[i] = *x;
      }
      if (Vec3{v[1], v[2], v[3]} == Vec3{0, 0, 0})
        r.fail("rotate", "rotation axis must not be zero");
      return Transform::rotate(v[0], {v[1], v[2], v[3]});
    };
    const toml::array* a = rn->as_array();
    if (!a || a->empty()) r.fail("rotate", "expected [degrees, x, y, z] or a list of them");
    if (a->get(0)->is_array()) {
      for (const auto& e : *a) {
        if (!e.is_array()) r.fail("rotate", "expected a list of [degrees, x, y, z]");
        rot = one(*e.as_array()) * rot;
      }
    } else {
      rot = one(*a);
    }
  }
  if (auto tv = r.optional_vec3("translate")) tr = Transform::translate(*tv);
  r.finish();
  return tr * rot * s * m;
}

static toml::table parse_default(std::string_view text) {
  return toml::parse("v = " + std::string(text));
}

ParamValue read_param_value(TableReader& r, const ParamSpec& spec, const toml::node& n) {
  const std::string_view key = spec.name;
  auto num = [&](const toml::node& x) {
    auto v = as_number(x);
    if (!v) r.fail_at(x, key, "expected a number, got " + type_name(x));
    check_range(r, x, key, *v, spec.min, spec.max, spec.min_exclusive, spec.max_exclusive);
    return *v;
  };
  auto vec = [&](const toml::node& x, size_t dim) {
    const toml::array* a = x.as_array();
    if (!a || a->size() != dim)
      r.fail_at(x, key, fmt::format("expected an array of {} numbers, got {}", dim, type_name(x)));
    Vec3 v;
    for (size_t i = 0; i < dim; ++i) v[int(i)] = num(*a->get(i));
    return v;
  };
  auto list = [&](const toml::node& x) -> const toml::array& {
    const toml::array* a = x.as_array();
    if (!a) r.fail_at(x, key, "expected an array, got " + type_name(x));
    return *a;
  };
  switch (spec.type) {
    case ParamType::Number:
      return num(n);
    case ParamType::Integer: {
      const auto iv = as_integer(n);
      if (!iv) r.fail_at(n, key, "expected an integer, got " + type_name(n));
      const auto v = *iv;
      check_range(r, n, key, double(v), spec.min, spec.max, spec.min_exclusive, spec.max_exclusive);
      return v;
    }
    case ParamType::Bool:
      if (!n.is_boolean()) r.fail_at(n, key, "expected true or false, got " + type_name(n));
      return *n.value<bool>();
    case ParamType::String: {
      if (!n.is_string()) r.fail_at(n, key, "expected a string, got " + type_name(n));
      std::string v = *n.value<std::string>();
      if (!spec.choices.empty() &&
          std::find(spec.choices.begin(), spec.choices.end(), v) == spec.choices.end()) {
        std::vector<std::string> cs(spec.choices.begin(), spec.choices.end());
        const std::string s = suggest(v, cs);
        r.fail_at(n, key,
                  fmt::format("unknown value \"{}\"{} (valid: {})", v,
                              s.empty() ? "" : fmt::format(" (did you mean \"{}\"?)", s),
                              join_choices(spec.choices)));
      }
      if (key == "file") {
        // File parameters are relative to the file that names them, like every path in a scene.
        std::filesystem::path p = v;
        const SourceLoc l = loc_of(n);
        if (p.is_relative() && !l.file.empty()) p = std::filesystem::path(l.file).parent_path() / p;
        if (!std::filesystem::exists(p))
          r.fail_at(n, key, fmt::format("file not found: {}", p.string()));
        return p.string();
      }
      return v;
    }
    case ParamType::Vec2: {
      const Vec3 v = vec(n, 2);
      return Vec2{v.x, v.y};
    }
    case ParamType::Vec3:
      return vec(n, 3);
    case ParamType::NumberList: {
      std::vector<double> out;
      for (const auto& e : list(n)) out.push_back(num(e));
      return out;
    }
    case ParamType::Vec3List: {
      std::vector<Vec3> out;
      for (const auto& e : list(n)) out.push_back(vec(e, 3));
      return out;
    }
    case ParamType::Vec3Grid: {
      std::vector<std::vector<Vec3>> out;
      for (const auto& row : list(n)) {
        out.emplace_back();
        for (const auto& e : list(row)) out.back().push_back(vec(e, 3));
      }
      return out;
    }
    case ParamType::NumberGrid: {
      std::vector<std::vector<double>> out;
      for (const auto& row : list(n)) {
        out.emplace_back();
        for (const auto& e : list(row)) out.back().push_back(num(e));
      }
      return out;
    }
    case ParamType::StringMap: {
      const toml::table* t = n.as_table();
      if (!t) r.fail_at(n, key, "expected a table { name = number, ... }");
      std::map<std::string, double> out;
      for (const auto& [k, v] : *t) {
        auto x = as_number(v);
        if (!x || !std::isfinite(*x))
          r.fail_at(v, key, fmt::format("constant '{}' must be a finite number", k.str()));
        out[std::string(k.str())] = *x;
      }
      return out;
    }
    case ParamType::Function: {
      const toml::table* t = n.as_table();
      if (!t) r.fail_at(n, key, "expected a table { type = \"...\", ... }");
      TableReader sub(*t, r.full_key(key));
      std::vector<std::string> names;
      for (const auto& f : org_functions()) names.emplace_back(f.name);
      std::vector<std::string_view> views(names.begin(), names.end());
      const std::string type = sub.string("type", "", views);
      if (type.empty()) sub.fail("type", "is required (one of: " + join_choices(views) + ")");
      auto nf = std::make_shared<NestedFunction>();
      nf->type = type;
      nf->values = sub.params(find_org_function(type)->params);
      sub.finish();
      return std::shared_ptr<const NestedFunction>(nf);
    }
  }
  r.fail_at(n, key, "unsupported parameter type");
}

ParamValues TableReader::params(std::span<const ParamSpec> specs) {
  ParamValues out;
  for (const ParamSpec& spec : specs) {
    const toml::node* n = node(spec.name);
    if (n) {
      out.set(std::string(spec.name), read_param_value(*this, spec, *n));
    } else if (spec.default_value.empty()) {
      fail(spec.name, "is required");
    } else if (spec.default_value != "none") {
      const toml::table d = parse_default(spec.default_value);
      out.set(std::string(spec.name), read_param_value(*this, spec, *d.get("v")));
    }
  }
  return out;
}

void TableReader::finish() {
  std::vector<std::string> known(known_.begin(), known_.end());
  for (const auto& [k, v] : t_) {
    if (used_.count(k.str())) continue;
    const std::string s = suggest(k.str(), known);
    std::string msg = "unknown key";
    if (!s.empty())
      msg += fmt::format(" (did you mean '{}'?)", s);
    else if (!known.empty()) {
      msg += " (valid keys here: ";
      for (size_t i = 0; i < known.size(); ++i) msg += (i ? ", " : "") + known[i];
      msg += ")";
    }
    throw SceneError(loc_of(k), full_key(k.str()), msg);
  }
}

std::string to_toml_text(const toml::table& t) {
  std::ostringstream os;
  os << toml::toml_formatter(
      t, toml::toml_formatter::default_flags & ~toml::format_flags::indentation);
  return os.str();
}

}  // namespace anamorph
