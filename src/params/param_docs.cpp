#include "params/param_docs.h"

#include <fmt/format.h>

#include <cstdio>
#include <sstream>

namespace anamorph {

std::string format_number(double x) {
  if (x == kInf) return "inf";
  if (x == -kInf) return "-inf";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", x);
  return buf;
}

std::string range_text(const ParamSpec& s) {
  if (s.min == -kInf && s.max == kInf) return {};
  // (fmt, not string concatenation: GCC 12 warns falsely about the latter here, -Wrestrict.)
  return fmt::format("{}{}, {}{}", s.min_exclusive || s.min == -kInf ? "(" : "[",
                     format_number(s.min), format_number(s.max),
                     s.max_exclusive || s.max == kInf ? ")" : "]");
}

std::string_view to_string(ParamType t) {
  switch (t) {
    case ParamType::Number:
      return "number";
    case ParamType::Integer:
      return "integer";
    case ParamType::Bool:
      return "bool";
    case ParamType::String:
      return "string";
    case ParamType::Vec2:
      return "[a, b]";
    case ParamType::Vec3:
      return "[x, y, z]";
    case ParamType::NumberList:
      return "number list";
    case ParamType::Vec3List:
      return "list of [x, y, z]";
    case ParamType::Vec3Grid:
      return "grid of [x, y, z]";
    case ParamType::NumberGrid:
      return "grid of numbers";
    case ParamType::StringMap:
      return "table name = number";
    case ParamType::Function:
      return "origin function";
    case ParamType::Color:
      return "colour";
    case ParamType::Texture:
      return "colour or texture";
    case ParamType::Transform:
      return "transform";
  }
  return "?";
}

namespace {

std::string cell(std::string_view text) {
  std::string r;
  for (char c : text) {
    if (c == '|')
      r += "\\|";
    else if (c == '\n')
      r += ' ';
    else
      r += c;
  }
  return r;
}

}  // namespace

std::string params_markdown_table(std::span<const ParamSpec> params) {
  std::ostringstream os;
  os << "| name | type | default | unit | range | meaning |\n|---|---|---|---|---|---|\n";
  for (const auto& p : params) {
    std::string def;
    if (!p.default_note.empty())
      def = cell(p.default_note);
    else if (p.default_value.empty())
      def = "*required*";
    else if (p.default_value == "none")
      def = "*optional*";
    else
      def.append("`").append(cell(p.default_value)).append("`");
    std::string range = range_text(with_world_range(p));
    if (!p.choices.empty()) {
      range.clear();
      for (auto c : p.choices) {
        if (!range.empty()) range += ", ";
        range += "`\"";
        range += c;
        range += "\"`";
      }
    }
    os << "| `" << p.name << "` | " << to_string(p.type) << " | " << def << " | " << cell(p.unit)
       << " | " << cell(range) << " | " << cell(p.doc) << " |\n";
  }
  return os.str();
}

}  // namespace anamorph
