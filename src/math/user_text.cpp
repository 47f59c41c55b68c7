#include "math/user_text.h"

#include <cstdint>
#include <cstdio>

namespace anamorph {

namespace {

// The length of the well-formed UTF-8 sequence starting at s[i] (2 to 4 bytes), or 0.
size_t utf8_sequence(std::string_view s, size_t i) {
  const auto c = static_cast<unsigned char>(s[i]);
  const size_t n = (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
  if (n == 0 || i + n > s.size()) return 0;
  uint32_t cp = c & (0x7F >> n);
  for (size_t k = 1; k < n; ++k) {
    const auto d = static_cast<unsigned char>(s[i + k]);
    if ((d & 0xC0) != 0x80) return 0;
    cp = cp << 6 | (d & 0x3F);
  }
  // Overlong forms, surrogates and values past U+10FFFF are not UTF-8.
  static constexpr uint32_t kMin[] = {0, 0, 0x80, 0x800, 0x10000};
  if (cp < kMin[n] || (cp >= 0xD800 && cp <= 0xDFFF) || cp > 0x10FFFF) return 0;
  return n;
}

void append_hex(std::string& out, const char* prefix, unsigned v, int digits) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%s%0*x", prefix, digits, v);
  out += buf;
}

}  // namespace

std::string printable(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c >= 0x20 && c < 0x7F) {
      out += char(c);
      ++i;
      continue;
    }
    if (c == '\n' || c == '\r' || c == '\t') {
      out += c == '\n' ? "\\n" : c == '\r' ? "\\r" : "\\t";
      ++i;
      continue;
    }
    const size_t n = c >= 0x80 ? utf8_sequence(s, i) : 0;
    if (n == 0) {  // another control character, or a byte that is not UTF-8
      append_hex(out, "\\x", c, 2);
      ++i;
      continue;
    }
    const auto c1 = static_cast<unsigned char>(s[i + 1]);
    if (n == 2 && c == 0xC2 && c1 < 0xA0)  // U+0080 to U+009F: C1 controls (0x9B is CSI)
      append_hex(out, "\\u", 0x80u + (c1 & 0x1Fu), 4);
    else
      out.append(s.substr(i, n));
    i += n;
  }
  return out;
}

std::string nul_in_path_message(std::string_view path, bool with_name) {
  return (with_name ? "the file name '" + printable(path) + "'" : std::string("the file name")) +
         " contains a NUL character (the system would read it as '" +
         printable(path.substr(0, path.find('\0'))) + "')";
}

}  // namespace anamorph
