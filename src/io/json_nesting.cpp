#include "io/json_nesting.h"

#include <fmt/format.h>

#include "math/input_limits.h"

namespace anamorph {

std::string json_nesting_error(std::string_view json) {
  int depth = 0;
  bool in_string = false;
  for (size_t i = 0; i < json.size(); ++i) {
    const char c = json[i];
    if (in_string) {
      if (c == '\\')
        ++i;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxNesting)
        return fmt::format(
            "nested more than {} levels deep (arrays and objects inside each other, at byte {})",
            kMaxNesting, i);
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return "";
}

}  // namespace anamorph
