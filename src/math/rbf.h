// Radial basis function interpolation of scattered data (the paper's "scattered data
// interpolation" for control points not on a grid):
//   S(x) = sum_i w_i phi(|x - x_i|) + q(x),   x in R^D (D = 2: image (u, v); D = 3: points of
// the unit sphere, where |x - x_i| is the chordal distance, as Pottmann & Eck's multiquadrics
// over the sphere), with a polynomial q of the kernel's minimum degree. The weights are solved
// once (Eigen, full-pivot LU) from S(x_i) = f_i, or with smoothing lambda from
// (K + lambda I) w + P c = f. Kernels, `epsilon` and degrees are SciPy's RBFInterpolator's, so
// the two agree to rounding. Values are Vec3 (surface points or directions).
#pragma once

#include <array>
#include <vector>

#include "math/vec.h"

namespace anamorph {

enum class RbfKernel { ThinPlate, Multiquadric, InverseMultiquadric, Gaussian, Cubic };

// The degree of the polynomial tail the kernel needs to be (conditionally) positive definite:
// 1 for thin_plate and cubic, 0 for multiquadric, -1 (none) for the others.
int rbf_polynomial_degree(RbfKernel k);

// The most data points accepted: the dense solve is O(n^3) in time and O(n^2) in memory (at
// 2000 points: 32 MB and about a second at load), and evaluation O(n) per ray.
inline constexpr int kRbfMaxPoints = 2000;

template <int D>
class Rbf {
 public:
  using Point = std::array<double, D>;
  static constexpr int kHessian = D * (D + 1) / 2;  // (0,0), (0,1), ..., (1,1), ... row-major

  // Throws std::invalid_argument naming the problem: fewer points than the polynomial needs,
  // two points at one position, values and points of different counts, a singular system
  // (e.g. collinear points under a linear tail), a non-finite solution.
  Rbf(std::vector<Point> centers, const std::vector<Vec3>& values, RbfKernel kernel,
      double epsilon = 1, double smoothing = 0);

  // S(x); grad (D entries, may be null): dS/dx_k; hess (kHessian entries, may be null): the
  // second derivatives in the upper triangle's row-major order. thin_plate's second derivatives
  // diverge like log r at its centers; within 1e-9 / epsilon of one they are taken there.
  Vec3 eval(const Point& x, Vec3* grad = nullptr, Vec3* hess = nullptr) const;

  size_t size() const { return centers_.size(); }

 private:
  std::vector<Point> centers_;
  std::vector<Vec3> weights_;
  std::array<Vec3, D + 1> tail_{};  // c0 + sum_k c_{k+1} x_k (zero where unused)
  RbfKernel kernel_;
  double epsilon_;
};

extern template class Rbf<2>;
extern template class Rbf<3>;

}  // namespace anamorph
