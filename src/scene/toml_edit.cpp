#include "scene/toml_edit.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <optional>
#include <vector>

#include "math/input_limits.h"
#include "params/toml_parse.h"

namespace anamorph {

namespace {

std::vector<std::string> split_key(const std::string& key) {
  std::vector<std::string> parts;
  for (size_t s = 0, e; s <= key.size(); s = e + 1) {
    e = key.find('.', s);
    if (e == std::string::npos) e = key.size();
    parts.push_back(key.substr(s, e - s));
  }
  return parts;
}

// The entry an array index names, or -1.
long array_index(const toml::array& a, const std::string& p) {
  char* end = nullptr;
  const long idx = std::strtol(p.c_str(), &end, 10);
  return p.empty() || *end || idx < 0 || size_t(idx) >= a.size() ? -1 : idx;
}

}  // namespace

bool valid_utf8(std::string_view s) {
  for (size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    const int n = c < 0x80           ? 1
                  : (c >> 5) == 0x6  ? 2
                  : (c >> 4) == 0xE  ? 3
                  : (c >> 3) == 0x1E ? 4
                                     : 0;
    if (n == 0 || i + n > s.size()) return false;
    uint32_t cp = n == 1 ? c : c & (0x7F >> n);
    for (int k = 1; k < n; ++k) {
      const auto d = static_cast<unsigned char>(s[i + k]);
      if ((d & 0xC0) != 0x80) return false;
      cp = cp << 6 | (d & 0x3F);
    }
    // Overlong forms, surrogates and values past U+10FFFF are not UTF-8.
    static constexpr uint32_t kMin[] = {0, 0, 0x80, 0x800, 0x10000};
    if (cp < kMin[n] || (cp >= 0xD800 && cp <= 0xDFFF) || cp > 0x10FFFF) return false;
    i += size_t(n);
  }
  return true;
}

namespace {

// A decimal integer too large for TOML's 64 bits (Python's 2**70 in `set=`): its value as a
// number, so that the key's reader can say it is out of range rather than "got a string".
std::optional<double> huge_integer(const std::string& text) {
  size_t i = text.find_first_not_of(" \t");
  if (i == std::string::npos) return std::nullopt;
  const bool negative = text[i] == '-';
  if (text[i] == '+' || text[i] == '-') ++i;
  const size_t end = text.find_last_not_of(" \t") + 1;
  if (i >= end || text.find_first_not_of("0123456789_", i) < end) return std::nullopt;
  std::string digits;
  for (size_t k = i; k < end; ++k)
    if (text[k] != '_') digits += text[k];
  // Only a magnitude TOML cannot hold (2^63 has 19 digits): other text that failed to parse,
  // such as 1__2 or 007, stays the string it is.
  if (digits.size() < 19 || digits[0] == '0') return std::nullopt;
  const double v = std::strtod(digits.c_str(), nullptr);  // (beyond doubles: the largest one)
  return (negative ? -1 : 1) * std::min(v, std::numeric_limits<double>::max());
}

}  // namespace

toml::table parse_value_text(const std::string& text, const std::string& key) {
  const std::string doc = "v = " + text;
  int line = 0, column = 0;
  if (const std::string e = toml_nesting_error(doc, &line, &column); !e.empty())
    throw SceneError({}, shown_key(key), "the value is " + e);
  try {
    return toml::parse(doc);
  } catch (const toml::parse_error&) {
    toml::table t;
    if (const auto big = huge_integer(text))
      t.insert("v", *big);
    else
      t.insert("v", text);  // a bare word: a string
    return t;
  }
}

std::string shown_key(const std::string& key) {
  return key.size() <= 80 ? key
                          : key.substr(0, 60) + "... (" + std::to_string(key.size()) + " bytes)";
}

void set_path(toml::table& root, const std::string& key, const toml::node& value,
              const SourceLoc& where) {
  const std::vector<std::string> parts = split_key(key);
  if (parts.size() > size_t(kMaxNesting))
    throw SceneError(where, shown_key(key),
                     fmt::format("a key of {} parts nests deeper than the {} levels anamorph reads",
                                 parts.size(), kMaxNesting));
  auto index = [&](const toml::array& a, const std::string& p) {
    const long idx = array_index(a, p);
    if (idx < 0)
      throw SceneError(
          where, key,
          fmt::format("'{}' is not a valid index (the array has {} entries)", p, a.size()));
    return size_t(idx);
  };
  toml::node* cur = &root;
  for (size_t i = 0; i + 1 < parts.size(); ++i) {
    const std::string& p = parts[i];
    if (toml::array* a = cur->as_array()) {
      cur = a->get(index(*a, p));
    } else if (toml::table* t = cur->as_table()) {
      if (!t->contains(p)) t->insert(p, toml::table{});
      cur = t->get(p);
    } else {
      throw SceneError(where, key, fmt::format("'{}' is not a table or an array", p));
    }
  }
  if (toml::array* a = cur->as_array()) {
    const size_t i = index(*a, parts.back());
    a->replace(a->cbegin() + long(i), value);
  } else if (toml::table* t = cur->as_table()) {
    t->insert_or_assign(parts.back(), value);
  } else {
    throw SceneError(where, key, "can only set keys of tables or entries of arrays");
  }
}

bool remove_path(toml::table& root, const std::string& key) {
  const std::vector<std::string> parts = split_key(key);
  toml::node* cur = &root;
  for (size_t i = 0; cur && i + 1 < parts.size(); ++i) {
    if (toml::array* a = cur->as_array()) {
      const long idx = array_index(*a, parts[i]);
      cur = idx < 0 ? nullptr : a->get(size_t(idx));
    } else if (toml::table* t = cur->as_table()) {
      cur = t->get(parts[i]);
    } else {
      cur = nullptr;
    }
  }
  if (!cur) return false;
  if (toml::array* a = cur->as_array()) {
    const long idx = array_index(*a, parts.back());
    if (idx < 0) return false;
    a->erase(a->cbegin() + idx);
    return true;
  }
  if (toml::table* t = cur->as_table()) return t->erase(parts.back()) > 0;
  return false;
}

}  // namespace anamorph
