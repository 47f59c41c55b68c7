// The one list of camera function types (adding a function = one line in kOrg / kDir), plus what
// is derived from the parameter tables: validation, construction from TOML text, Markdown docs.
#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <vector>

#include "camera/dir_basic.h"
#include "camera/dir_dependent.h"
#include "camera/dir_expression.h"
#include "camera/dir_scattered.h"
#include "camera/functions.h"
#include "camera/org_basic.h"
#include "camera/org_expression.h"
#include "camera/org_mesh.h"
#include "camera/org_quadric.h"
#include "camera/org_revolution.h"
#include "camera/org_scattered.h"
#include "camera/org_spline.h"
#include "camera/org_superquadric.h"
#include "camera/table_functions.h"
#include "params/param_docs.h"
#include "params/param_toml.h"
#include "params/read_params.h"
#include "params/toml_parse.h"

namespace anamorph {

namespace {
const OrgFunctionInfo* const kOrg[] = {
    &kPointOrgInfo,        &kPlaneOrgInfo,      &kSphereOrgInfo,    &kCylinderOrgInfo,
    &kConeOrgInfo,         &kTorusOrgInfo,      &kEllipsoidOrgInfo, &kQuadricOrgInfo,
    &kSuperquadricOrgInfo, &kBezierOrgInfo,     &kBSplineOrgInfo,   &kNurbsOrgInfo,
    &kMeshOrgInfo,         &kExpressionOrgInfo, &kScatteredOrgInfo, &kTableOrgInfo};
const DirFunctionInfo* const kDir[] = {
    &kConstantDirInfo,   &kFromSurfaceDirInfo, &kTowardDirInfo,          &kAwayFromDirInfo,
    &kNormalDirInfo,     &kTangentUDirInfo,    &kTangentVDirInfo,        &kDeviatedNormalDirInfo,
    &kExpressionDirInfo, &kScatteredDirInfo,   &kScatteredSphereDirInfo, &kTableDirInfo};

template <class Info, size_t N>
std::vector<Info> to_list(const Info* const (&infos)[N]) {
  std::vector<Info> v;
  for (auto* i : infos) v.push_back(*i);
  return v;
}

template <class Info>
std::string names_of(std::span<const Info> infos) {
  std::string s;
  for (const auto& i : infos) s += (s.empty() ? "" : ", ") + std::string(i.name);
  return s;
}

// Variant alternative index of each ParamType (the order of ParamValue).
size_t variant_index(ParamType t) {
  switch (t) {
    case ParamType::Number:
      return 0;
    case ParamType::Integer:
      return 1;
    case ParamType::Bool:
      return 2;
    case ParamType::String:
      return 3;
    case ParamType::Vec2:
      return 4;
    case ParamType::Vec3:
      return 5;
    case ParamType::NumberList:
      return 6;
    case ParamType::Vec3List:
      return 7;
    case ParamType::Vec3Grid:
      return 8;
    case ParamType::NumberGrid:
      return 9;
    case ParamType::StringMap:
      return 10;
    case ParamType::Function:
    case ParamType::Texture:  // (or 5, a colour)
      return 11;
    case ParamType::Color:
      return 5;
    case ParamType::Transform:
      return 12;
  }
  return size_t(-1);
}

// (The words of the scene's range errors: one range-message format, range_error.)
void check_number(const ParamSpec& s, double x) {
  const std::string e = range_error(x, s.min, s.max, s.min_exclusive, s.max_exclusive);
  if (!e.empty()) throw ParamError(std::string(s.name), std::string(s.name) + ": " + e);
}

const ParamSpec* find_spec(std::span<const ParamSpec> specs, std::string_view name) {
  for (const auto& s : specs)
    if (s.name == name) return &s;
  return nullptr;
}

std::string spec_names(std::span<const ParamSpec> specs) {
  std::string s;
  for (const auto& p : specs) s += (s.empty() ? "" : ", ") + std::string(p.name);
  return s;
}

// --- TOML text to ParamValues (the same conversions as the scene parser, without positions) ---

ParamValues values_from_table(std::span<const ParamSpec> specs, const toml::table& t);

// The walker (read_params.h) with errors as ParamError and no positions: the same checks and
// words as the scene parser.
ParamWalk registry_walk() {
  ParamWalk w;
  w.hooks.fail = [](const toml::node&, std::string_view key, const std::string& msg) {
    throw ParamError(std::string(key), fmt::format("{}: {}", key, msg));
  };
  w.hooks.nested = [](const toml::table& t, const ParamSpec& spec) {
    const std::string key(spec.name);
    const auto type = t["type"].value<std::string>();
    if (!type) throw ParamError(key, key + ": the table needs type = \"...\"");
    const OrgFunctionInfo* info = find_org_function(*type);
    if (!info)
      throw ParamError(
          key, key + ": unknown type '" + *type + "' (valid: " + names_of(org_functions()) + ")");
    toml::table rest = t;
    rest.erase("type");
    auto nf = std::make_shared<NestedFunction>();
    nf->type = *type;
    try {
      nf->values = values_from_table(info->params, rest);
    } catch (const ParamError& e) {  // named from the outer table: "surface.radius"
      const std::string_view what = e.what();
      const bool keyed = what.starts_with(e.key + ":");
      throw ParamError(fmt::format("{}.{}", key, e.key),
                       keyed ? fmt::format("{}.{}", key, what) : fmt::format("{}: {}", key, what));
    }
    return std::shared_ptr<const NestedFunction>(nf);
  };
  return w;
}

ParamValues values_from_table(std::span<const ParamSpec> specs, const toml::table& t) {
  ParamWalk w = registry_walk();
  w.unknown_key = [specs](const toml::key& k, const std::string&) {
    throw ParamError(std::string(k.str()), "unknown key '" + std::string(k.str()) +
                                               "' (valid: " + spec_names(specs) + ")");
  };
  w.hooks.fail = [fail = w.hooks.fail](const toml::node& at, std::string_view key,
                                       const std::string& msg) {
    if (msg == "is required")
      throw ParamError(std::string(key), "missing required key '" + std::string(key) + "'");
    fail(at, key, msg);
  };
  return read_params(t, {specs}, w);
}

void markdown_section(std::ostringstream& os, std::string_view kind, std::string_view name,
                      std::string_view doc, std::span<const ParamSpec> params) {
  os << "### " << kind << " `" << name << "`\n\n" << doc << "\n\n";
  if (params.empty()) {
    os << "No parameters.\n\n";
    return;
  }
  os << params_markdown_table(params) << "\n";
}

}  // namespace

std::span<const OrgFunctionInfo> org_functions() {
  static const std::vector<OrgFunctionInfo> list = to_list(kOrg);
  return list;
}
std::span<const DirFunctionInfo> dir_functions() {
  static const std::vector<DirFunctionInfo> list = to_list(kDir);
  return list;
}
const OrgFunctionInfo* find_org_function(std::string_view name) {
  for (const auto& f : org_functions())
    if (f.name == name) return &f;
  return nullptr;
}
const DirFunctionInfo* find_dir_function(std::string_view name) {
  for (const auto& f : dir_functions())
    if (f.name == name) return &f;
  return nullptr;
}

namespace {
template <class Info>
std::vector<std::string_view> names_list(std::span<const Info> infos) {
  std::vector<std::string_view> names;
  for (const auto& f : infos) names.push_back(f.name);
  return names;
}
}  // namespace

const ParamSpec& org_type_spec() {
  static const std::vector<std::string_view> names = names_list(org_functions());
  static const ParamSpec spec{"type", ParamType::String, "", "The origin function.", -kInf, kInf,
                              names};
  return spec;
}

const ParamSpec& dir_type_spec() {
  static const std::vector<std::string_view> names = names_list(dir_functions());
  static const ParamSpec spec{"type", ParamType::String, "", "The direction function.", -kInf, kInf,
                              names};
  return spec;
}

namespace {

void check_choice(const ParamSpec& s, const std::string& key, const std::string& str) {
  if (s.choices.empty() || std::find(s.choices.begin(), s.choices.end(), str) != s.choices.end())
    return;
  std::string valid;
  for (auto c : s.choices) valid += (valid.empty() ? "" : ", ") + std::string(c);
  throw ParamError(key, key + ": unknown value \"" + str + "\" (valid: " + valid + ")");
}

// Every number a value of the declared type holds within the declared range (a switch over the
// closed set of parameter types).
void check_value(const ParamSpec& s, const std::string& key, const ParamValue& v) {
  switch (s.type) {
    case ParamType::Number:
      check_number(s, std::get<double>(v));
      break;
    case ParamType::Integer:
      check_number(s, double(std::get<int64_t>(v)));
      break;
    case ParamType::Vec2:
      check_number(s, std::get<Vec2>(v).x);
      check_number(s, std::get<Vec2>(v).y);
      break;
    case ParamType::Vec3:
      for (int i = 0; i < 3; ++i) check_number(s, std::get<Vec3>(v)[i]);
      break;
    case ParamType::NumberList:
      for (double x : std::get<std::vector<double>>(v)) check_number(s, x);
      break;
    case ParamType::Vec3List:
      for (const Vec3& p : std::get<std::vector<Vec3>>(v))
        for (int i = 0; i < 3; ++i) check_number(s, p[i]);
      break;
    case ParamType::Vec3Grid:
      for (const auto& row : std::get<std::vector<std::vector<Vec3>>>(v))
        for (const Vec3& p : row)
          for (int i = 0; i < 3; ++i) check_number(s, p[i]);
      break;
    case ParamType::NumberGrid:
      for (const auto& row : std::get<std::vector<std::vector<double>>>(v))
        for (double x : row) check_number(s, x);
      break;
    case ParamType::StringMap:
      for (const auto& [k, x] : std::get<std::map<std::string, double>>(v)) check_number(s, x);
      break;
    case ParamType::String:
      check_choice(s, key, std::get<std::string>(v));
      break;
    case ParamType::Function:
      if (!std::get<std::shared_ptr<const NestedFunction>>(v))
        throw ParamError(key, key + " must not be empty");
      break;
    case ParamType::Color:
      for (int i = 0; i < 3; ++i) check_number(s, std::get<Vec3>(v)[i]);
      break;
    case ParamType::Bool:
    case ParamType::Texture:
    case ParamType::Transform:
      break;
  }
}

}  // namespace

void check_params(std::span<const ParamSpec> specs, const ParamValues& values) {
  for (const auto& [name, value] : values.all())
    if (!find_spec(specs, name))
      throw ParamError(name, "unknown key '" + name + "' (valid: " + spec_names(specs) + ")");
  for (const auto& s : specs) {
    const std::string key(s.name);
    if (!values.has(s.name)) {
      if (s.default_value.empty()) throw ParamError(key, "missing required key '" + key + "'");
      continue;
    }
    const ParamValue& v = values.all().find(s.name)->second;
    if (v.index() != variant_index(s.type))
      throw ParamError(key, key + " must be of type " + std::string(to_string(s.type)));
    check_value(s, key, v);
  }
}

ParamValues params_from_toml(std::span<const ParamSpec> specs, std::string_view toml_text) {
  toml::table t;
  try {
    t = parse_toml(toml_text);
  } catch (const toml::parse_error& e) {
    throw ParamError("", "invalid TOML: " + std::string(e.description()));
  }
  return values_from_table(specs, t);
}

std::unique_ptr<OrgFunction> make_org(std::string_view type, std::string_view toml_text) {
  const OrgFunctionInfo* info = find_org_function(type);
  if (!info)
    throw ParamError("type", "unknown origin function '" + std::string(type) +
                                 "' (valid: " + names_of(org_functions()) + ")");
  return info->create(params_from_toml(info->params, toml_text));
}

std::unique_ptr<DirFunction> make_dir(std::string_view type, std::string_view toml_text) {
  const DirFunctionInfo* info = find_dir_function(type);
  if (!info)
    throw ParamError("type", "unknown direction function '" + std::string(type) +
                                 "' (valid: " + names_of(dir_functions()) + ")");
  return info->create(params_from_toml(info->params, toml_text));
}

std::string function_params_markdown() {
  std::ostringstream os;
  os << "## Origin functions (`camera.org`)\n\n"
        "Each maps the image position (u, v) in [0,1]^2 (u left to right, v top to bottom) "
        "linearly onto its own parameter ranges and gives the ray origin, its derivatives and "
        "the surface normal. Right-handed world, +y up.\n\n";
  for (const auto& f : org_functions()) markdown_section(os, "org", f.name, f.doc, f.params);
  os << "## Direction functions (`camera.dir`)\n\n"
        "Each gives the ray direction at (u, v) (normalized by the camera); dependent directions "
        "read the origin surface at the same (u, v).\n\n";
  for (const auto& f : dir_functions()) markdown_section(os, "dir", f.name, f.doc, f.params);
  return os.str();
}

}  // namespace anamorph
