#include "app/form_factor_output.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "math/user_text.h"

namespace anamorph::app {

namespace {

// Column c's name: an object's, or the environment's.
const std::string& column(const FormFactors& f, size_t c) {
  static const std::string env(kEnvironmentColumn);
  return c < f.names.size() ? f.names[c] : env;
}

// A JSON string: escaped, and any byte that is not UTF-8 replaced (U+FFFD): names from models
// are bytes from anywhere.
std::string json_string(const std::string& s) {
  return nlohmann::json(s).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

void require_finite(double v, const std::string& what) {
  if (!std::isfinite(v))
    throw std::runtime_error(fmt::format("{} is {}, not a number that can be reported", what, v));
}

}  // namespace

void check_finite(const FormFactors& f, const std::vector<Color>* B, const PathRadiance* path) {
  for (size_t r = 0; r < f.rows.size(); ++r) {
    const std::string& from = f.names[size_t(f.rows[r])];
    require_finite(f.areas[size_t(f.rows[r])], "the area of '" + from + "'");
    for (size_t c = 0; c < f.F[r].size(); ++c) {
      const std::string pair = "F('" + from + "' -> '" + column(f, c) + "')";
      require_finite(f.F[r][c], pair);
      require_finite(f.error[r][c], "the standard error of " + pair);
    }
  }
  require_finite(f.worst_reciprocity_z, "the worst reciprocity difference");
  for (size_t i = 0; B && i < B->size(); ++i)
    for (int c = 0; c < 3; ++c) {
      require_finite((*B)[i][c], "the radiosity of '" + f.names[i] + "'");
      if (path) require_finite(path->mean[i][c] + path->error[i][c], "the path tracer's radiance");
    }
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string q = "\"";
  for (const char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string to_csv(const FormFactors& f) {
  std::string s = "from,to,area_from,F,stderr\n";
  for (size_t r = 0; r < f.rows.size(); ++r)
    for (size_t c = 0; c <= f.names.size(); ++c)
      s += fmt::format("{},{},{:.10g},{:.10g},{:.3g}\n", csv_field(f.names[size_t(f.rows[r])]),
                       csv_field(column(f, c)), f.areas[size_t(f.rows[r])], f.F[r][c],
                       f.error[r][c]);
  return s;
}

std::string to_json(const FormFactors& f, const std::vector<Color>* B) {
  std::string s = "{\n  \"objects\": [";
  for (size_t i = 0; i < f.names.size(); ++i)
    s += fmt::format("{}{{\"name\": {}, \"area\": {:.10g}}}", i ? ", " : "",
                     json_string(f.names[i]), f.areas[i]);
  s += "],\n  \"columns\": [";
  for (size_t i = 0; i <= f.names.size(); ++i) s += (i ? ", " : "") + json_string(column(f, i));
  const auto matrix = [&](const std::vector<std::vector<double>>& m, const char* fmtspec) {
    std::string t = "[";
    for (size_t r = 0; r < m.size(); ++r) {
      t += r ? ",\n    [" : "\n    [";
      for (size_t c = 0; c < m[r].size(); ++c)
        t += (c ? ", " : "") + fmt::format(fmt::runtime(fmtspec), m[r][c]);
      t += "]";
    }
    return t + "]";
  };
  s += "],\n  \"rows\": [";
  for (size_t r = 0; r < f.rows.size(); ++r)
    s += (r ? ", " : "") + json_string(f.names[size_t(f.rows[r])]);
  s += "],\n  \"unmeasured\": [";
  for (size_t i = 0, k = 0; i < f.no_row.size(); ++i)
    if (!f.no_row[i].empty())
      s += fmt::format("{}{{\"name\": {}, \"reason\": {}}}", k++ ? ", " : "",
                       json_string(f.names[i]), json_string(f.no_row[i]));
  s += "],\n  \"F\": " + matrix(f.F, "{:.10g}") + ",\n  \"stderr\": " + matrix(f.error, "{:.3g}");
  s += fmt::format(",\n  \"reciprocity_worst_z\": {:.4g}", f.worst_reciprocity_z);
  if (B) {
    s += ",\n  \"radiosity\": [";
    for (size_t i = 0; i < B->size(); ++i)
      s += fmt::format("{}[{:.10g}, {:.10g}, {:.10g}]", i ? ", " : "", (*B)[i].x, (*B)[i].y,
                       (*B)[i].z);
    s += "]";
  }
  return s + "\n}\n";
}

void print_table(const FormFactors& f) {
  fmt::print("form factors F(from -> to) +- standard error ({} objects, {} = nothing hit)\n",
             f.names.size(), kEnvironmentColumn);
  for (size_t r = 0; r < f.rows.size(); ++r) {
    const size_t i = size_t(f.rows[r]);
    double sum = 0;
    fmt::print("  {} (area {:.6g})\n", printable(f.names[i]), f.areas[i]);
    for (size_t c = 0; c <= f.names.size(); ++c) {
      sum += f.F[r][c];
      if (f.F[r][c] > 0)
        fmt::print("    -> {:<24} {:.6f} +- {:.6f}\n", printable(column(f, c)), f.F[r][c],
                   f.error[r][c]);
    }
    fmt::print("    row sum {:.6f}\n", sum);
  }
  for (size_t i = 0; i < f.no_row.size(); ++i)
    if (!f.no_row[i].empty())
      fmt::print("  {}: no row ({}); a receiver only\n", printable(f.names[i]),
                 printable(f.no_row[i]));
  if (f.worst_i >= 0)
    fmt::print("reciprocity A_i F_ij = A_j F_ji: worst {} / {} differ by {:.2f} standard errors\n",
               printable(f.names[size_t(f.worst_i)]), printable(f.names[size_t(f.worst_j)]),
               f.worst_reciprocity_z);
}

void print_radiosity(const FormFactors& f, const std::vector<Color>& B, const PathRadiance& p) {
  fmt::print("radiosity (I - rho F) B = E; mean radiance B / pi against the path tracer's\n");
  for (size_t i = 0; i < B.size(); ++i) {
    const Color L = B[i] / kPi;
    double z = 0;
    for (int c = 0; c < 3; ++c)
      if (p.error[i][c] > 0) z = std::max(z, std::abs(L[c] - p.mean[i][c]) / p.error[i][c]);
    fmt::print(
        "  {:<24} B/pi ({:.5f}, {:.5f}, {:.5f})  path ({:.5f}, {:.5f}, {:.5f}) +- "
        "{:.5f}  ({} standard errors)\n",
        printable(f.names[i]), L.x, L.y, L.z, p.mean[i].x, p.mean[i].y, p.mean[i].z,
        std::max({p.error[i].x, p.error[i].y, p.error[i].z}),
        z < 1e6 ? fmt::format("{:.1f}", z)
                : fmt::format("{:.3g}", std::min(z, std::numeric_limits<double>::max())));
  }
}

}  // namespace anamorph::app
