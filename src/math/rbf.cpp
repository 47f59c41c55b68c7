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
// a = eps^2 g'(s) / s and b = eps^4 (g''(s) - g'(s) / s) / s^2: the unit kernel's, scaled.
struct Radial {
  double phi, a, b;
};

Radial unit_radial(RbfKernel k, double s) {
  switch (k) {
    case RbfKernel::Gaussian: {  // exp(-s^2)
      const double g = std::exp(-s * s);
      return {g, -2 * g, 4 * g};
    }
    case RbfKernel::InverseMultiquadric: {  // 1 / sqrt(1 + s^2)
      const double q = 1 / std::sqrt(1 + s * s), q3 = q * q * q;
      return {q, -q3, 3 * q3 * q * q};
    }
    case RbfKernel::Multiquadric: {  // -sqrt(1 + s^2), SciPy's sign
      const double m = std::sqrt(1 + s * s);
      return {-m, -1 / m, 1 / (m * m * m)};
    }
    case RbfKernel::Cubic:  // s^3
      return {s * s * s, 3 * s, s > 0 ? 3 / s : 0.0};
    case RbfKernel::ThinPlate: {  // s^2 log s; g'' diverges like log s at 0: taken at 1e-9
      if (s == 0) return {0, 0, 0};
      const double ss = std::max(s, 1e-9), l = std::log(ss);
      return {s * s * std::log(s), 2 * l + 1, 2 / (ss * ss)};
    }
  }
  return {0, 0, 0};
}

Radial radial(RbfKernel k, double eps, double r) {
  const Radial g = unit_radial(k, eps * r);
  const double e2 = eps * eps;
  return {g.phi, g.a * e2, g.b * e2 * e2};
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

template <int D>
Vec3 Rbf<D>::eval(const Point& x, Vec3* grad, Vec3* hess) const {
  Vec3 f = tail_[0];
  for (int k = 0; k < D; ++k) f += tail_[size_t(k + 1)] * x[size_t(k)];
  if (grad)
    for (int k = 0; k < D; ++k) grad[k] = tail_[size_t(k + 1)];
  if (hess)
    for (int k = 0; k < kHessian; ++k) hess[k] = Vec3{};
  for (size_t i = 0; i < centers_.size(); ++i) {
    Point d;
    for (int k = 0; k < D; ++k) d[size_t(k)] = x[size_t(k)] - centers_[i][size_t(k)];
    const Radial r = radial(kernel_, epsilon_, distance<D>(x, centers_[i]));
    const Vec3& w = weights_[i];
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

template class Rbf<2>;
template class Rbf<3>;

}  // namespace anamorph
