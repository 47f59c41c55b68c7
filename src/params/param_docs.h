// Documentation generated from parameter tables: the Markdown table of a table's keys, and the
// words for types and ranges that the docs, the JSON Schema and error messages share.
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "params/params.h"

namespace anamorph {

// "[0, inf)", "(0, 1]", or "" when unbounded.
std::string range_text(const ParamSpec& s);
// A number as the docs write it: "inf", "-inf", or up to 10 significant digits.
std::string format_number(double x);

// The Markdown table (name | type | default | unit | range | meaning) of a parameter table.
std::string params_markdown_table(std::span<const ParamSpec> params);

}  // namespace anamorph
