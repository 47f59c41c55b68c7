#include "camera/scattered_common.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iterator>

#include "math/input_limits.h"

namespace anamorph {

std::vector<ScatteredDatum> read_scattered_data(const ParamValues& v, std::string_view key) {
  std::vector<ScatteredDatum> out;
  const auto& rows = v.number_grid(key);
  for (size_t i = 0; i < rows.size(); ++i) {
    if (rows[i].size() != 5)
      throw ParamError(std::string(key), std::string(key) + ": point " + std::to_string(i) +
                                             " has " + std::to_string(rows[i].size()) +
                                             " numbers; each is [u, v, x, y, z]");
    for (int k = 0; k < 2; ++k)
      if (!(std::abs(rows[i][size_t(k)]) <= kScatteredUvLimit))
        throw ParamError(std::string(key),
                         fmt::format("point {}: {} = {} is out of range (must be within [-{:g}, "
                                     "{:g}]: image positions are in [0, 1], and points farther out "
                                     "would make the interpolation's system overflow or lose all "
                                     "precision)",
                                     i, k ? "v" : "u", rows[i][size_t(k)], kScatteredUvLimit,
                                     kScatteredUvLimit));
    const Vec3 value{rows[i][2], rows[i][3], rows[i][4]};
    // (Positions, or directions, of the world: math/input_limits.h.)
    if (!within_world(value))
      throw ParamError(std::string(key),
                       fmt::format("{}: point {}: [{:g}, {:g}, {:g}] is not within the {:g} "
                                   "scene units of the origin the world holds",
                                   key, i, value.x, value.y, value.z, kMaxCoordinate));
    out.push_back({{rows[i][0], rows[i][1]}, value});
  }
  return out;
}

RbfKernel read_rbf_kernel(const ParamValues& v) {
  const std::string& k = v.string("kernel");
  const auto* it = std::find(std::begin(kRbfKernelNames), std::end(kRbfKernelNames), k);
  return RbfKernel(it - std::begin(kRbfKernelNames));  // check_params has checked the choice
}

}  // namespace anamorph
