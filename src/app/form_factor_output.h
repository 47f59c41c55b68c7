// What `anamorph formfactors` writes: the table on the terminal (names escaped), the long-form
// CSV (RFC 4180: names quoted where they hold a comma, quote or line break) and the JSON
// (strings escaped, bytes that are not UTF-8 replaced). Every number is checked finite first: a
// value that is not is an error naming it, never printed as nan or inf.
#pragma once

#include <string>
#include <vector>

#include "render/form_factors.h"

namespace anamorph::app {

// Throws std::runtime_error naming the first entry of `f` (or of `B`, `path`) that is not a
// finite number (a defect: the measurement and the solve return finite values).
void check_finite(const FormFactors& f, const std::vector<Color>* B = nullptr,
                  const PathRadiance* path = nullptr);

// A CSV field (RFC 4180): quoted, with quotes doubled, when it holds a comma, a quote, CR or LF.
std::string csv_field(const std::string& s);

std::string to_csv(const FormFactors& f);
std::string to_json(const FormFactors& f, const std::vector<Color>* B);
void print_table(const FormFactors& f);
void print_radiosity(const FormFactors& f, const std::vector<Color>& B, const PathRadiance& p);

}  // namespace anamorph::app
