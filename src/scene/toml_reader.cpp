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

static void check_range(const TableReader& r, const toml::node& n, std::string_view key, double v,
                        double lo, double hi) {
  const std::string e = range_error(v, lo, hi);
  if (!e.empty()) r.fail_at(n, key, e);
}

double TableReader::number(std::string_view key, double def, double lo, double hi) {
  const toml::node* n = node(key);
  if (!n) return def;
  auto v = toml_number(*n);
  if (!v) fail(key, "expected a number, got " + toml_type_name(*n));
  check_range(*this, *n, key, *v, lo, hi);
  return *v;
}

double TableReader::required_number(std::string_view key, double lo, double hi) {
  if (!has(key)) fail(key, "is required");
  return number(key, 0, lo, hi);
}

// Integers, and floats with an integral value (animated keys interpolate as floats).
int64_t TableReader::integer(std::string_view key, int64_t def, int64_t lo, int64_t hi) {
  const toml::node* n = node(key);
  if (!n) return def;
  auto v = toml_integer(*n);
  if (!v) fail(key, "expected an integer, got " + toml_type_name(*n));
  check_range(*this, *n, key, double(*v), double(lo), double(hi));
  return *v;
}

bool TableReader::boolean(std::string_view key, bool def) {
  const toml::node* n = node(key);
  if (!n) return def;
  if (!n->is_boolean()) fail(key, "expected true or false, got " + toml_type_name(*n));
  return *n->value<bool>();
}

std::string TableReader::string(std::string_view key, std::string def,
                                std::span<const std::string_view> choices) {
  const toml::node* n = node(key);
  if (!n) return def;
  if (!n->is_string()) fail(key, "expected a string, got " + toml_type_name(*n));
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
    auto x = toml_number(*a->get(size_t(i)));
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
  if (!v) fail(key, "expected an array of 3 numbers [x, y, z], got " + toml_type_name(*n));
  check_finite_vec(*this, *n, key, *v);
  return v;
}

Vec3 TableReader::vec3(std::string_view key, Vec3 def) { return optional_vec3(key).value_or(def); }

Color TableReader::color(std::string_view key, Color def) {
  const toml::node* n = node(key);
  if (!n) return def;
  if (auto x = toml_number(*n)) {
    check_range(*this, *n, key, *x, 0, kInf);
    return Color(*x);
  }
  auto v = as_vec3(*n);
  if (!v) fail(key, "expected a colour [r, g, b] or a number, got " + toml_type_name(*n));
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
      auto x = toml_number(*a->get(size_t(i)));
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
    if (auto x = toml_number(*sn))
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
        auto x = toml_number(*a.get(size_t(i)));
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
  ParamTomlHooks h;
  h.fail = [&](const toml::node& at, std::string_view key, const std::string& msg) {
    r.fail_at(at, key, msg);
  };
  h.file = [&](const toml::node& at, std::string_view key, const std::string& v) {
    // File parameters are relative to the file that names them, like every path in a scene.
    std::filesystem::path p = v;
    const SourceLoc l = loc_of(at);
    if (p.is_relative() && !l.file.empty()) p = std::filesystem::path(l.file).parent_path() / p;
    if (!std::filesystem::exists(p))
      r.fail_at(at, key, fmt::format("file not found: {}", p.string()));
    return p.string();
  };
  h.nested = [&](const toml::table& t, std::string_view key) {
    TableReader sub(t, r.full_key(key));
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
  };
  return param_from_toml(spec, n, h);
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
