#include "scene/toml_reader.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include <fmt/format.h>

#include "camera/functions.h"
#include "math/user_text.h"

namespace anamorph {

namespace {
constexpr std::string_view kTypeKey[] = {"type"};
}  // namespace

SceneError::SceneError(const SourceLoc& l, std::string k, const std::string& msg)
    : std::runtime_error([&] {
        // File names, keys and the values a message quotes are the user's text: escaped.
        std::string where = l.file.empty() ? std::string("--set") : printable(l.file);
        if (l.line > 0) where += fmt::format(":{}:{}", l.line, l.column);
        return k.empty() ? fmt::format("{}: {}", where, printable(msg))
                         : fmt::format("{}: {}: {}", where, printable(k), printable(msg));
      }()),
      loc(l),
      key(std::move(k)),
      message(msg) {}

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

void TableReader::fail(std::string_view key, const std::string& msg) const {
  // At the key's value when it has one (a value from --set or [[animate]] has no place in a
  // file, and says so), else at the table.
  const toml::node* n = t_.get(key);
  throw SceneError(loc_of(n ? *n : static_cast<const toml::node&>(t_)), full_key(key), msg);
}

void TableReader::fail_at(const toml::node& n, std::string_view key, const std::string& msg) const {
  throw SceneError(loc_of(n), full_key(key), msg);
}

namespace {

// A nested table: a texture (by texture_schema) or an origin function (by its own table).
std::shared_ptr<const NestedFunction> read_nested(const TableReader& outer, const toml::table& t,
                                                  const ParamSpec& spec) {
  const TableReader sub(t, outer.full_key(spec.name));
  auto nf = std::make_shared<NestedFunction>();
  if (spec.type == ParamType::Texture) {
    nf->values = sub.params(texture_schema());
    nf->type = nf->values.string("type");
    return nf;
  }
  nf->type = sub.selector(org_type_spec());
  nf->values = sub.params({find_org_function(nf->type)->params}, kTypeKey);
  return nf;
}

}  // namespace

ParamWalk TableReader::walk(std::span<const std::string_view> also) const {
  ParamWalk w;
  w.also = also;
  w.hooks.fail = [this](const toml::node& at, std::string_view key, const std::string& msg) {
    fail_at(at, key, msg);
  };
  w.hooks.file = [this](const toml::node& at, std::string_view key, const std::string& v) {
    // File parameters are relative to the file that names them, like every path in a scene.
    std::filesystem::path p = v;
    const SourceLoc l = loc_of(at);
    if (p.is_relative() && !l.file.empty()) p = std::filesystem::path(l.file).parent_path() / p;
    if (!std::filesystem::exists(p))
      fail_at(at, key, fmt::format("file not found: {}", p.string()));
    return p.string();
  };
  w.hooks.nested = [this](const toml::table& t, const ParamSpec& spec) {
    return read_nested(*this, t, spec);
  };
  w.unknown_key = [this](const toml::key& k, const std::string& msg) {
    throw SceneError(loc_of(k), full_key(k.str()), msg);
  };
  return w;
}

ParamValues TableReader::params(std::initializer_list<std::span<const ParamSpec>> groups,
                                std::span<const std::string_view> also) const {
  return read_params(t_, groups, walk(also));
}

std::string TableReader::selector(const ParamSpec& spec) const {
  const toml::node* n = t_.get(spec.name);
  if (!n && spec.default_value.empty())
    fail(spec.name, "is required (one of: " + join_choices(spec.choices) + ")");
  // (A selector's default is a TOML string: its text without the quotes.)
  if (!n) return std::string(spec.default_value.substr(1, spec.default_value.size() - 2));
  return std::get<std::string>(param_from_toml(spec, *n, walk({}).hooks));
}

ParamValues TableReader::params(const TableSchema& schema,
                                std::span<const std::string_view> also) const {
  // The selector first (its default or a required value), then every key of its form.
  const TableVariant& form =
      *schema.variant(selector(*find_param({schema.common}, schema.selector)));
  return params({schema.common, form.params}, also);
}

std::string to_toml_text(const toml::table& t) {
  std::ostringstream os;
  os << toml::toml_formatter(
      t, toml::toml_formatter::default_flags & ~toml::format_flags::indentation);
  return os.str();
}

}  // namespace anamorph
