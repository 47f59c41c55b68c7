#include "math/rbf.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace anamorph {

namespace {

// phi(r) = g(eps r) for the unit kernel g, and the terms of its derivatives with d = x - x_i,
// r = |d|:  d phi / dx = a d,  d^2 phi / dx^2 = a I + b d d^T,  a = phi'(r) / r,
// b = (phi''(r) - a) / r^2 (finite forms, so r = 0 needs no division). With s = eps r these are
// a = eps^2 g'(s) / s and b = eps^4 (g''(s) - g'(s) / s) / s^2. Every kernel but the cubic is a
// function of s^2, so no square root is taken for them, and the thin plate takes one logarithm:
// s^2 log s = s^2 log(s^2) / 2.
struct Radial {
  double phi, a, b;
};

template <RbfKernel K>
[[gnu::always_inline]] inline Radial radial2(double e2, double r2) {
  const double s2 = e2 * r2, e4 = e2 * e2;
  if constexpr (K == RbfKernel::Gaussian) {  // exp(-s^2)
    const double g = std::exp(-s2);
    return {g, -2 * g * e2, 4 * g * e4};
  } else if constexpr (K == RbfKernel::InverseMultiquadric) {  // 1 / sqrt(1 + s^2)
    const double q = 1 / std::sqrt(1 + s2), q3 = q * q * q;
    return {q, -q3 * e2, 3 * q3 * q * q * e4};
  } else if constexpr (K == RbfKernel::Multiquadric) {  // -sqrt(1 + s^2), SciPy's sign
    const double m = std::sqrt(1 + s2);
    return {-m, -e2 / m, e4 / (m * m * m)};
  } else if constexpr (K == RbfKernel::Cubic) {  // s^3
    const double sv = std::sqrt(s2);
    return {sv * s2, 3 * sv * e2, sv > 0 ? 3 / sv * e4 : 0.0};
  } else {  // thin plate, s^2 log s; g'' diverges like log s at 0: taken at s = 1e-9 within it
    if (s2 == 0) return {0, 0, 0};
    const double c2 = std::max(s2, 1e-18), l = std::log(c2);
    return {0.5 * s2 * (s2 == c2 ? l : std::log(s2)), (l + 1) * e2, 2 / c2 * e4};
  }
}

Radial radial(RbfKernel k, double eps, double r) {
  const double e2 = eps * eps, r2 = r * r;
  switch (k) {
    case RbfKernel::Gaussian:
      return radial2<RbfKernel::Gaussian>(e2, r2);
    case RbfKernel::InverseMultiquadric:
      return radial2<RbfKernel::InverseMultiquadric>(e2, r2);
    case RbfKernel::Multiquadric:
      return radial2<RbfKernel::Multiquadric>(e2, r2);
    case RbfKernel::Cubic:
      return radial2<RbfKernel::Cubic>(e2, r2);
    case RbfKernel::ThinPlate:
      return radial2<RbfKernel::ThinPlate>(e2, r2);
  }
  return {0, 0, 0};
}

template <int D>
int tail_terms(RbfKernel k) {
  const int d = rbf_polynomial_degree(k);
  return d < 0 ? 0 : (d == 0 ? 1 : D + 1);
}

template <int D>
double distance(const std::array<double, D>& a, const std::array<double, D>& b) {
  double s = 0;
  for (int k = 0; k < D; ++k) s += (a[size_t(k)] - b[size_t(k)]) * (a[size_t(k)] - b[size_t(k)]);
  return std::sqrt(s);
}

}  // namespace

int rbf_polynomial_degree(RbfKernel k) {
  switch (k) {
    case RbfKernel::ThinPlate:
    case RbfKernel::Cubic:
      return 1;
    case RbfKernel::Multiquadric:
      return 0;
    case RbfKernel::InverseMultiquadric:
    case RbfKernel::Gaussian:
      return -1;
  }
  return -1;
}

template <int D>
Rbf<D>::Rbf(std::vector<Point> centers, const std::vector<Vec3>& values, RbfKernel kernel,
            double epsilon, double smoothing)
    : centers_(std::move(centers)), kernel_(kernel), epsilon_(epsilon) {
  const int n = int(centers_.size()), m = tail_terms<D>(kernel);
  if (values.size() != centers_.size())
    throw std::invalid_argument("as many values as points are needed");
  if (n > kRbfMaxPoints)
    throw std::invalid_argument("at most " + std::to_string(kRbfMaxPoints) +
                                " points (the solve grows with the cube of their number), not " +
                                std::to_string(n));
  const int need = std::max(m, 1);
  if (n < need)
    throw std::invalid_argument("at least " + std::to_string(need) +
                                " points are needed with this kernel, not " + std::to_string(n));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < i; ++j)
      if (centers_[size_t(i)] == centers_[size_t(j)])
        throw std::invalid_argument("points " + std::to_string(j) + " and " + std::to_string(i) +
                                    " are at the same position");
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n + m, n + m);
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n + m, 3);
  for (int i = 0; i < n; ++i) {
    const Point& xi = centers_[size_t(i)];
    for (int j = 0; j < n; ++j)
      A(i, j) = radial(kernel, epsilon, distance<D>(xi, centers_[size_t(j)])).phi;
    A(i, i) += smoothing;
    for (int k = 0; k < m; ++k) A(i, n + k) = A(n + k, i) = k == 0 ? 1.0 : xi[size_t(k - 1)];
    for (int c = 0; c < 3; ++c) rhs(i, c) = values[size_t(i)][c];
  }
  if (!A.allFinite())
    throw std::invalid_argument(
        "the kernel's values overflow (the shape times the largest distance between points is "
        "too large for this kernel): use a smaller shape");
  // The polynomial part first: under a linear tail the points must span it (its rank is
  // judged on P alone, whose entries are O(1); the whole matrix's pivots, with a large
  // smoothing on the diagonal, would make any relative threshold misjudge it).
  if (m > 1 && Eigen::FullPivLU<Eigen::MatrixXd>(A.topRightCorner(n, m)).rank() < m)
    throw std::invalid_argument(
        D == 2 ? "the system is singular: the points must not all lie on one line"
               : "the system is singular: the points must not all lie on one plane (one circle "
                 "of the sphere)");
  // Then the solve (partial pivoting: blocked, several times faster than full pivoting at a
  // thousand points), judged by its residual: with distinct points and a spanning tail the
  // system is non-singular in exact arithmetic, so what can fail is conditioning (e.g. a
  // gaussian so wide that its columns coincide to rounding).
  const Eigen::MatrixXd x = A.partialPivLu().solve(rhs);
  const double scale =
      A.cwiseAbs().maxCoeff() * x.cwiseAbs().maxCoeff() + rhs.cwiseAbs().maxCoeff();
  if (!x.allFinite() || (A * x - rhs).cwiseAbs().maxCoeff() > 1e-9 * scale)
    throw std::invalid_argument(
        "the system is singular (points too close together for this kernel and shape? try a "
        "larger shape or some smoothing)");
  weights_.resize(size_t(n));
  for (int i = 0; i < n; ++i) weights_[size_t(i)] = {x(i, 0), x(i, 1), x(i, 2)};
  for (int k = 0; k < m; ++k) tail_[size_t(k)] = {x(n + k, 0), x(n + k, 1), x(n + k, 2)};
}

// The sum over centers for one kernel, with the gradient and Hessian only when asked for: the
// kernel's switch outside the loop, its math inlined into it.
template <int D, RbfKernel K>
Vec3 rbf_sum(const std::vector<std::array<double, D>>& centers, const std::vector<Vec3>& weights,
             const std::array<Vec3, D + 1>& tail, double eps, const std::array<double, D>& x,
             Vec3* grad, Vec3* hess) {
  Vec3 f = tail[0];
  for (int k = 0; k < D; ++k) f += tail[size_t(k + 1)] * x[size_t(k)];
  if (grad)
    for (int k = 0; k < D; ++k) grad[k] = tail[size_t(k + 1)];
  if (hess)
    for (int k = 0; k < D * (D + 1) / 2; ++k) hess[k] = Vec3{};
  const double e2 = eps * eps;
  for (size_t i = 0; i < centers.size(); ++i) {
    std::array<double, D> d;
    double r2 = 0;
    for (int k = 0; k < D; ++k) {
      d[size_t(k)] = x[size_t(k)] - centers[i][size_t(k)];
      r2 += d[size_t(k)] * d[size_t(k)];
    }
    const Radial r = radial2<K>(e2, r2);
    const Vec3& w = weights[i];
    f += w * r.phi;
    if (grad)
      for (int k = 0; k < D; ++k) grad[k] += w * (r.a * d[size_t(k)]);
    if (hess)
      for (int k = 0, h = 0; k < D; ++k)
        for (int l = k; l < D; ++l, ++h)
          hess[h] += w * ((k == l ? r.a : 0.0) + r.b * d[size_t(k)] * d[size_t(l)]);
  }
  return f;
}

template <int D>
Vec3 Rbf<D>::eval(const Point& x, Vec3* grad, Vec3* hess) const {
  switch (kernel_) {
    case RbfKernel::Gaussian:
      return rbf_sum<D, RbfKernel::Gaussian>(centers_, weights_, tail_, epsilon_, x, grad, hess);
    case RbfKernel::InverseMultiquadric:
      return rbf_sum<D, RbfKernel::InverseMultiquadric>(centers_, weights_, tail_, epsilon_, x,
                                                        grad, hess);
    case RbfKernel::Multiquadric:
      return rbf_sum<D, RbfKernel::Multiquadric>(centers_, weights_, tail_, epsilon_, x, grad,
                                                 hess);
    case RbfKernel::Cubic:
      return rbf_sum<D, RbfKernel::Cubic>(centers_, weights_, tail_, epsilon_, x, grad, hess);
    case RbfKernel::ThinPlate:
      return rbf_sum<D, RbfKernel::ThinPlate>(centers_, weights_, tail_, epsilon_, x, grad, hess);
  }
  return {};
}

template class Rbf<2>;
template class Rbf<3>;

}  // namespace anamorph
