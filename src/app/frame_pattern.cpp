#include "app/frame_pattern.h"

#include <fmt/format.h>

#include <cctype>
#include <cstdlib>

namespace anamorph::app {

std::optional<std::string> frame_pattern_error(const std::string& pattern) {
  int conversions = 0;
  for (size_t i = pattern.find('%'); i != std::string::npos; i = pattern.find('%', i + 1)) {
    if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
      ++i;
      continue;
    }
    size_t j = i + 1;
    while (j < pattern.size() && std::isdigit(static_cast<unsigned char>(pattern[j]))) ++j;
    if (j == pattern.size() || pattern[j] != 'd')
      return fmt::format("'{}' is not a frame-number pattern (%d, %4d, %04d)",
                         pattern.substr(i, j + 1 - i));
    // (the width's digits, a leading 0 being the flag that pads with zeros)
    const std::string digits = pattern.substr(i + 1, j - i - 1);
    const size_t first = digits.find_first_not_of('0');
    const std::string width = first == std::string::npos ? "" : digits.substr(first);
    if (width.size() > 2 || (!width.empty() && std::stoi(width) > kMaxFrameWidth))
      return fmt::format("the frame number's field width {} is more than {} characters", width,
                         kMaxFrameWidth);
    ++conversions;
    i = j;
  }
  if (conversions != 1)
    return conversions == 0 ? "it has no frame-number pattern"
                            : "it has more than one frame-number pattern";
  return std::nullopt;
}

bool parse_frame_range(const std::string& text, int* first, int* last) {
  auto number = [](const std::string& t, int* v) {
    if (t.empty()) return false;
    char* end = nullptr;
    const long x = std::strtol(t.c_str(), &end, 10);
    if (*end || x < -1000000000 || x > 1000000000) return false;
    *v = int(x);
    return true;
  };
  const size_t colon = text.find(':');
  if (colon == std::string::npos) return number(text, first) && number(text, last);
  return number(text.substr(0, colon), first) && number(text.substr(colon + 1), last);
}

}  // namespace anamorph::app
