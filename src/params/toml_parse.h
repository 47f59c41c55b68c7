// Parsing TOML text from users (scene files, included files, `--set` values, the editor's
// documents and edits, camera tables given as text) with its nesting bounded first.
//
// toml++ recurses once per level of a dotted key or table header (`a.a.a... = 1` of 50,000 parts
// overflowed the stack inside it), and so do the tree's destructor and every walk over it. Its
// own limit (TOML_MAX_NESTED_VALUES) covers arrays and inline tables only. So the text is scanned
// first: the depth of every key (header parts, dotted key parts and the arrays and inline tables
// around it) must stay within kMaxNesting (math/input_limits.h).
#pragma once

#include <string_view>

#include <toml++/toml.h>

namespace anamorph {

// toml::parse(text, source) after the nesting check. Throws toml::parse_error, for nesting with
// the line and column where the limit is passed.
toml::table parse_toml(std::string_view text, std::string_view source = {});

// The error message when `text` nests deeper than kMaxNesting, with *line and *column (from 1)
// where; "" when it does not. (The scan skips strings and comments; it does not validate TOML,
// which toml++ does after it.)
std::string toml_nesting_error(std::string_view text, int* line, int* column);

}  // namespace anamorph
