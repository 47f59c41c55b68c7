// Piecewise-constant 1D and 2D distributions for importance sampling (lights, environment maps).
#pragma once

#include <algorithm>
#include <vector>

#include "math/vec.h"

namespace anamorph {

class Distribution1D {
 public:
  Distribution1D() = default;
  explicit Distribution1D(std::vector<double> f) : f_(std::move(f)), cdf_(f_.size() + 1, 0.0) {
    for (size_t i = 0; i < f_.size(); ++i) cdf_[i + 1] = cdf_[i] + std::max(0.0, f_[i]);
    total_ = cdf_.back();
    if (total_ > 0)
      for (double& c : cdf_) c /= total_;
    else
      for (size_t i = 0; i < cdf_.size(); ++i) cdf_[i] = double(i) / double(f_.size());
  }
  size_t size() const { return f_.size(); }
  double total() const { return total_; }
  // Discrete choice: index and its probability.
  size_t sample_discrete(double u, double* pmf) const {
    const size_t i = find(u);
    if (pmf) *pmf = cdf_[i + 1] - cdf_[i];
    return i;
  }
  double pmf(size_t i) const { return cdf_[i + 1] - cdf_[i]; }
  // The probability of the indices before i (where i's share of [0, 1) begins).
  double cdf(size_t i) const { return cdf_[i]; }
  // Continuous on [0,1): position and density.
  double sample_continuous(double u, double* pdf, size_t* index = nullptr) const {
    const size_t i = find(u);
    const double w = cdf_[i + 1] - cdf_[i];
    const double du = w > 0 ? (u - cdf_[i]) / w : 0.5;
    if (pdf) *pdf = w * double(f_.size());
    if (index) *index = i;
    return (double(i) + du) / double(f_.size());
  }
  double pdf_continuous(double x) const {
    const size_t i = std::min(size_t(std::max(0.0, x) * double(f_.size())), f_.size() - 1);
    return pmf(i) * double(f_.size());
  }

 private:
  size_t find(double u) const {
    const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), u);
    return std::clamp<size_t>(size_t(it - cdf_.begin()) - 1, 0, f_.size() - 1);
  }
  std::vector<double> f_, cdf_;
  double total_ = 0;
};

// f(u, v) on [0,1]^2 given as nv rows of nu values.
class Distribution2D {
 public:
  Distribution2D() = default;
  Distribution2D(const std::vector<double>& f, size_t nu, size_t nv) {
    std::vector<double> marginal(nv);
    for (size_t v = 0; v < nv; ++v) {
      rows_.emplace_back(
          std::vector<double>(f.begin() + long(v * nu), f.begin() + long((v + 1) * nu)));
      marginal[v] = rows_.back().total();
    }
    marginal_ = Distribution1D(std::move(marginal));
  }
  Vec2 sample(Vec2 u, double* pdf) const {
    double pv, pu;
    size_t row;
    const double v = marginal_.sample_continuous(u.y, &pv, &row);
    const double x = rows_[row].sample_continuous(u.x, &pu);
    *pdf = pv * pu;
    return {x, v};
  }
  double pdf(Vec2 p) const {
    const size_t row =
        std::min(size_t(std::max(0.0, p.y) * double(rows_.size())), rows_.size() - 1);
    return marginal_.pdf_continuous(p.y) * rows_[row].pdf_continuous(p.x);
  }

 private:
  std::vector<Distribution1D> rows_;
  Distribution1D marginal_;
};

}  // namespace anamorph
