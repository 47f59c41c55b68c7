#include "params/toml_parse.h"

#include <fmt/format.h>

#include <memory>
#include <string>
#include <vector>

#include "math/input_limits.h"

namespace anamorph {

namespace {

bool bare_key_char(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
         c == '-';
}

// One pass over the text tracking the depth of every key: a table header's parts, then each
// key's parts on top of it, and one level for every array or inline table a value opens.
class NestingScan {
 public:
  explicit NestingScan(std::string_view t) : t_(t) {}
  std::string run();
  int line = 1, column = 1;

 private:
  struct Open {
    int depth;  // the depth of the array or inline table itself
    char kind;  // '[' or '{'
  };
  char peek(size_t k = 0) const { return i_ + k < t_.size() ? t_[i_ + k] : '\0'; }
  bool at_end() const { return i_ >= t_.size(); }
  void step() {
    if (t_[i_] == '\n') ++line_, line_start_ = i_ + 1;
    ++i_;
  }
  void skip_spaces() {
    while (peek() == ' ' || peek() == '\t') ++i_;
  }
  void skip_to_line_end() {
    while (!at_end() && peek() != '\n') ++i_;
  }
  void skip_string();
  int key_parts();
  bool too_deep(int depth, size_t at);
  void header();
  void key(std::vector<Open>& open);
  void value_char(std::vector<Open>& open);

  std::string_view t_;
  size_t i_ = 0, line_start_ = 0;
  int line_ = 1;
  int header_ = 0;  // parts of the current [table] header
  int value_ = 0;   // the depth of the value being read
  bool expect_key_ = true;
  std::string error_;
};

// At a quote: past the string (basic or literal, one line or several).
void NestingScan::skip_string() {
  const char q = peek();
  const bool multi = peek(1) == q && peek(2) == q;
  i_ += multi ? 3 : 1;
  while (!at_end()) {
    const char c = peek();
    if (c == '\\' && q == '"') {
      i_ += 2;
      continue;
    }
    if (!multi && c == '\n') return;  // (toml++ reports the unterminated string)
    if (c == q && (!multi || (peek(1) == q && peek(2) == q))) {
      i_ += multi ? 3 : 1;
      for (int extra = 0; multi && extra < 2 && peek() == q; ++extra) ++i_;
      return;
    }
    step();
  }
}

// At a key: its dotted parts (bare or quoted), whitespace around the dots allowed.
int NestingScan::key_parts() {
  int parts = 0;
  for (;;) {
    skip_spaces();
    if (peek() == '"' || peek() == '\'') {
      skip_string();
    } else {
      const size_t s = i_;
      while (bare_key_char(peek())) ++i_;
      if (i_ == s) break;
    }
    ++parts;
    skip_spaces();
    if (peek() != '.') break;
    ++i_;
  }
  return parts;
}

bool NestingScan::too_deep(int depth, size_t at) {
  if (depth <= kMaxNesting) return false;
  line = line_;
  column = int(at - line_start_) + 1;
  error_ = fmt::format(
      "nested more than {} levels deep (a dotted key or table header of too many parts, or "
      "arrays and inline tables inside each other)",
      kMaxNesting);
  return true;
}

// At the '[' of a table header: its parts become the base of the keys below it.
void NestingScan::header() {
  ++i_;
  const bool array = peek() == '[';
  if (array) ++i_;
  skip_spaces();
  const size_t at = i_;
  header_ = key_parts() + (array ? 1 : 0);  // (an array of tables: one level more)
  if (too_deep(header_, at)) return;
  while (!at_end() && peek() != '\n' && peek() != '#') {
    if (peek() == '"' || peek() == '\'')
      skip_string();
    else
      ++i_;
  }
}

void NestingScan::key(std::vector<Open>& open) {
  if (peek() == '}' && !open.empty()) {  // an empty inline table, or a trailing comma
    value_ = open.back().depth;
    open.pop_back();
    ++i_;
    expect_key_ = false;
    return;
  }
  const size_t at = i_;
  const int base = open.empty() ? header_ : open.back().depth;
  value_ = base + std::max(key_parts(), 1);
  expect_key_ = false;
  if (too_deep(value_, at)) return;
  skip_spaces();
  if (peek() == '=') ++i_;
}

void NestingScan::value_char(std::vector<Open>& open) {
  const char c = peek();
  if (c == '"' || c == '\'') {
    skip_string();
  } else if (c == '[' || c == '{') {
    open.push_back({value_, c});
    if (too_deep(value_ + 1, i_)) return;
    ++i_;
    value_ = open.back().depth + 1;
    expect_key_ = c == '{';
  } else if (c == ']' || c == '}') {
    if (!open.empty()) value_ = open.back().depth, open.pop_back();
    ++i_;
  } else if (c == ',' && !open.empty()) {
    ++i_;
    if (open.back().kind == '{')
      expect_key_ = true;
    else
      value_ = open.back().depth + 1;
  } else {
    ++i_;
  }
}

std::string NestingScan::run() {
  std::vector<Open> open;
  while (!at_end() && error_.empty()) {
    const char c = peek();
    if (c == ' ' || c == '\t' || c == '\r') {
      ++i_;
    } else if (c == '\n') {
      step();
      if (open.empty()) expect_key_ = true;
    } else if (c == '#') {
      skip_to_line_end();
    } else if (expect_key_ && open.empty() && c == '[') {
      header();
    } else if (expect_key_) {
      key(open);
    } else {
      value_char(open);
    }
  }
  return error_;
}

}  // namespace

std::string toml_nesting_error(std::string_view text, int* line, int* column) {
  NestingScan scan(text);
  std::string e = scan.run();
  *line = scan.line;
  *column = scan.column;
  return e;
}

toml::table parse_toml(std::string_view text, std::string_view source) {
  int line = 0, column = 0;
  std::string e = toml_nesting_error(text, &line, &column);
  if (!e.empty()) {
    const toml::source_position at{toml::source_index(line), toml::source_index(column)};
    throw toml::parse_error(e.c_str(), at,
                            source.empty() ? nullptr : std::make_shared<const std::string>(source));
  }
  return toml::parse(text, source);
}

}  // namespace anamorph
