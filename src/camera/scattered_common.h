// What the scattered-data functions (org `scattered`, dir `scattered` and `scattered_sphere`)
// share: the kernel keys and the reading of [u, v, x, y, z] data rows.
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "camera/functions.h"
#include "math/rbf.h"

namespace anamorph {

// How far outside the image ([0, 1]) a data point's u and v may lie: 1e6. The interpolation's
// system mixes the kernel at the points' distances with the points' coordinates; beyond about
// 1e15 the coordinates swamp the rest in double precision and the solve fails for no fault of the
// data (points reported as collinear), and beyond 1e154 squared distances overflow. 1e6 leaves
// every kernel well inside both (tested at the bound).
inline constexpr double kScatteredUvLimit = 1e6;
// The largest shape parameter: the kernels see shape times a distance (at most 3e6 in the plane,
// 2 on the sphere), and cubic's cube of it must stay finite with room to spare.
inline constexpr double kRbfShapeLimit = 1e50;

inline constexpr std::string_view kRbfKernelNames[] = {
    "thin_plate", "multiquadric", "inverse_multiquadric", "gaussian", "cubic"};  // RbfKernel order

inline constexpr ParamSpec kRbfKernelParam{
    "kernel",
    ParamType::String,
    "\"thin_plate\"",
    "The radial basis phi(r): thin_plate (r^2 log r, the smoothest bending; with its linear tail "
    "it reproduces planes), multiquadric (-sqrt(1 + (shape r)^2), constant tail), "
    "inverse_multiquadric (1 / sqrt(1 + (shape r)^2)), gaussian (exp(-(shape r)^2)) or cubic "
    "(r^3, linear tail): SciPy's RBFInterpolator kernels and minimum polynomial degrees.",
    -kInf,
    kInf,
    kRbfKernelNames};
inline constexpr ParamSpec kRbfShapeParam{
    "shape",
    ParamType::Number,
    "1",
    "The shape parameter (SciPy's epsilon) of multiquadric, inverse_multiquadric and gaussian: "
    "larger = narrower bumps, each data point pulling a smaller neighbourhood. The kernels see "
    "shape * r, as SciPy's; thin_plate and cubic surfaces do not depend on it unless smoothing "
    "is on (it then scales the smoothing's effect).",
    0,
    kRbfShapeLimit,
    {},
    true};
inline constexpr ParamSpec kRbfSmoothingParam{
    "smoothing", ParamType::Number, "0",
    "lambda: 0 passes through every data point exactly; larger values trade that for a smoother "
    "result (lambda is added to the system's diagonal, as SciPy's `smoothing`).",
    0};

// One data row [u, v, x, y, z].
struct ScatteredDatum {
  Vec2 uv;
  Vec3 value;
};

// Reads `key` as [u, v, x, y, z] rows; ParamError naming the row that is not five numbers or
// whose u or v lies beyond kScatteredUvLimit.
std::vector<ScatteredDatum> read_scattered_data(const ParamValues& v, std::string_view key);

RbfKernel read_rbf_kernel(const ParamValues& v);

// The planar interpolant of `points` ([u, v, x, y, z] rows) with the table's kernel, shape and
// smoothing: value(datum, i) gives row i's value (the point itself, or its unit direction).
// Interpolator errors become a ParamError on `points`.
template <class Value>
Rbf<2> planar_rbf(const ParamValues& v, Value value);

// Runs make(), turning the interpolator's std::invalid_argument into a ParamError on `key`.
template <class F>
auto rbf_param_errors(std::string_view key, F make) {
  try {
    return make();
  } catch (const std::invalid_argument& e) {
    throw ParamError(std::string(key), std::string(key) + ": " + e.what());
  }
}

template <class Value>
Rbf<2> planar_rbf(const ParamValues& v, Value value) {
  std::vector<Rbf<2>::Point> at;
  std::vector<Vec3> values;
  const auto data = read_scattered_data(v, "points");
  for (size_t i = 0; i < data.size(); ++i) {
    at.push_back({data[i].uv.x, data[i].uv.y});
    values.push_back(value(data[i], i));
  }
  return rbf_param_errors("points", [&] {
    return Rbf<2>(std::move(at), values, read_rbf_kernel(v), v.number("shape"),
                  v.number("smoothing"));
  });
}

}  // namespace anamorph
