// How deep JSON text nests, checked before a parser builds it: the editor's request bodies
// (nlohmann::json; the server's walks over a value recurse, and 20,000 levels overflowed a
// request thread's stack) and glTF files (tinygltf converts `extras` and `extensions`
// recursively: a file of 100,000 brackets faulted). The bound is kMaxNesting
// (math/input_limits.h).
#pragma once

#include <string>
#include <string_view>

namespace anamorph {

// "" when `json` nests at most kMaxNesting arrays and objects deep; otherwise what and at which
// byte. Strings are skipped; nothing else is validated (the parser does that after).
std::string json_nesting_error(std::string_view json);

}  // namespace anamorph
