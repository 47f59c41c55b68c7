// Helpers of the `anamorph solve` tests: where `anamorph project` puts a point, the numbers of a
// key in a solved scene's text, the residual `solve` printed.
#pragma once

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "cli_util.h"

namespace anamorph::test {

// Where `anamorph project` puts `p` through `scene`, in pixels (the first position).
inline std::vector<double> projected(const std::string& scene, const std::vector<double>& p) {
  const CliResult r =
      run_cli(fmt::format("project '{}' --point {},{},{}", scene, p[0], p[1], p[2]), 60);
  EXPECT_EQ(r.code, 0) << r.out;
  double x = NAN, y = NAN;
  EXPECT_EQ(std::sscanf(r.out.c_str(), "px %lf py %lf", &x, &y), 2) << r.out;
  return {x, y};
}

// The numbers of `key = ...` in TOML text (one, or an array's, nested arrays flattened; the
// value may span lines).
inline std::vector<double> numbers_of(const std::string& text, const std::string& key) {
  std::smatch m;
  EXPECT_TRUE(std::regex_search(text, m, std::regex("\n" + key + R"( = (\[[^=#]*\]|[^\n#]*))")))
      << key << " not in:\n"
      << text;
  std::vector<double> v;
  std::string s = m.size() > 1 ? m[1].str() : "";
  for (char& c : s)
    if (c == ',' || c == '[' || c == ']') c = ' ';
  std::istringstream is(s);
  for (double x; is >> x;) v.push_back(x);
  return v;
}

// The residual `solve` printed for constraint i, in its unit.
inline double printed_residual(const std::string& out, int i) {
  std::smatch m;
  const std::regex re(fmt::format(R"(camera\.constraint\[{}\] +\w+ +residual (\S+))", i));
  EXPECT_TRUE(std::regex_search(out, m, re)) << out;
  return m.size() > 1 ? std::stod(m[1].str()) : NAN;
}

}  // namespace anamorph::test
