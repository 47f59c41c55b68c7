#include "camera/bspline.h"

#include <algorithm>
#include <cmath>

namespace anamorph::spline {

int find_span(int n, int p, double t, std::span<const double> knots) {
  const double lo = knots[size_t(p)], hi = knots[size_t(n + 1)];
  if (!(t > lo)) t = lo;  // also maps NaN to the domain start
  if (t >= hi) {
    // The last non-empty span [knots[i], knots[i+1]) with knots[i+1] = hi.
    int i = n;
    while (i > p && knots[size_t(i)] == hi) --i;
    return i;
  }
  // Binary search for knots[mid] <= t < knots[mid + 1].
  int low = p, high = n + 1;
  int mid = (low + high) / 2;
  while (t < knots[size_t(mid)] || t >= knots[size_t(mid + 1)]) {
    if (t < knots[size_t(mid)])
      high = mid;
    else
      low = mid;
    mid = (low + high) / 2;
  }
  return mid;
}

void basis_funs(int span, double t, int p, std::span<const double> knots, double* out) {
  double left[kMaxBezierDegree + 1], right[kMaxBezierDegree + 1];
  out[0] = 1.0;
  for (int j = 1; j <= p; ++j) {
    left[j] = t - knots[size_t(span + 1 - j)];
    right[j] = knots[size_t(span + j)] - t;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      const double temp = out[r] / (right[r + 1] + left[j - r]);
      out[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    out[j] = saved;
  }
}

namespace {

// A2.3; PC > 0 fixes the degree at compile time (loops unroll for the common low degrees),
// PC = 0 takes it from p.
template <int PC>
void ders_impl(int span, double t, int p_runtime, int nd, std::span<const double> knots,
               BasisDers& ders) {
  const int p = PC > 0 ? PC : p_runtime;
  constexpr int kN = (PC > 0 ? PC : kMaxBezierDegree) + 1;
  // ndu holds the basis functions (upper triangle with the diagonal) and, unlike the book, the
  // *reciprocals* of the knot differences (lower triangle): each difference is divided by once
  // here instead of in every use below, which makes this several times faster.
  double ndu[kN][kN];
  double left[kN], right[kN];
  ndu[0][0] = 1.0;
  for (int j = 1; j <= p; ++j) {
    left[j] = t - knots[size_t(span + 1 - j)];
    right[j] = knots[size_t(span + j)] - t;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      ndu[j][r] = 1.0 / (right[r + 1] + left[j - r]);
      const double temp = ndu[r][j - 1] * ndu[j][r];
      ndu[r][j] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    ndu[j][j] = saved;
  }
  for (int j = 0; j <= p; ++j) ders[0][j] = ndu[j][p];
  for (int k = 1; k <= nd; ++k)
    for (int j = 0; j <= p; ++j) ders[k][j] = 0.0;
  if (nd == 0) return;

  double a[2][kN];
  for (int r = 0; r <= p; ++r) {
    int s1 = 0, s2 = 1;
    a[0][0] = 1.0;
    for (int k = 1; k <= std::min(nd, p); ++k) {
      double d = 0.0;
      const int rk = r - k, pk = p - k;
      if (r >= k) {
        a[s2][0] = a[s1][0] * ndu[pk + 1][rk];
        d = a[s2][0] * ndu[rk][pk];
      }
      const int j1 = rk >= -1 ? 1 : -rk;
      const int j2 = (r - 1 <= pk) ? k - 1 : p - r;
      for (int j = j1; j <= j2; ++j) {
        a[s2][j] = (a[s1][j] - a[s1][j - 1]) * ndu[pk + 1][rk + j];
        d += a[s2][j] * ndu[rk + j][pk];
      }
      if (r <= pk) {
        a[s2][k] = -a[s1][k - 1] * ndu[pk + 1][r];
        d += a[s2][k] * ndu[r][pk];
      }
      ders[k][r] = d;
      std::swap(s1, s2);
    }
  }
  // Multiply by p! / (p - k)!.
  double f = p;
  for (int k = 1; k <= nd; ++k) {
    for (int j = 0; j <= p; ++j) ders[k][j] *= f;
    f *= (p - k);
  }
}

}  // namespace

void ders_basis_funs(int span, double t, int p, int nd, std::span<const double> knots,
                     BasisDers& ders) {
  switch (p) {
    case 1:
      return ders_impl<1>(span, t, p, nd, knots, ders);
    case 2:
      return ders_impl<2>(span, t, p, nd, knots, ders);
    case 3:
      return ders_impl<3>(span, t, p, nd, knots, ders);
    case 4:
      return ders_impl<4>(span, t, p, nd, knots, ders);
    case 5:
      return ders_impl<5>(span, t, p, nd, knots, ders);
    default:
      return ders_impl<0>(span, t, p, nd, knots, ders);
  }
}

void bernstein_ders(int p, double t, BasisDers& ders) {
  // Build B_{.,k} for k = 0..p with the de Casteljau-like recurrence
  // B_{i,k} = (1 - t) B_{i,k-1} + t B_{i-1,k-1}, keeping degrees p-2 and p-1 for derivatives:
  // B'_{i,p} = p (B_{i-1,p-1} - B_{i,p-1}),
  // B''_{i,p} = p (p-1) (B_{i-2,p-2} - 2 B_{i-1,p-2} + B_{i,p-2}).
  double b[kMaxBezierDegree + 1] = {1.0};
  double b1[kMaxBezierDegree + 1] = {}, b2[kMaxBezierDegree + 1] = {};
  const double s = 1.0 - t;
  for (int k = 1; k <= p; ++k) {
    if (k == p - 1) std::copy(b, b + k, b2);  // degree p-2 (k-1 entries + 1)
    if (k == p) std::copy(b, b + k, b1);      // degree p-1
    b[k] = t * b[k - 1];
    for (int i = k - 1; i > 0; --i) b[i] = s * b[i] + t * b[i - 1];
    b[0] = s * b[0];
  }
  for (int i = 0; i <= p; ++i) {
    ders[0][i] = b[i];
    const double lo1 = i >= 1 ? b1[i - 1] : 0.0, hi1 = i <= p - 1 ? b1[i] : 0.0;
    ders[1][i] = p >= 1 ? p * (lo1 - hi1) : 0.0;
    if (p >= 2) {
      const double a0 = i >= 2 ? b2[i - 2] : 0.0, a1 = (i >= 1 && i - 1 <= p - 2) ? b2[i - 1] : 0.0,
                   a2 = i <= p - 2 ? b2[i] : 0.0;
      ders[2][i] = p * (p - 1) * (a0 - 2 * a1 + a2);
    } else {
      ders[2][i] = 0.0;
    }
  }
}

std::vector<double> clamped_knots(int num_ctrl, int p) {
  const int n = num_ctrl - 1, m = n + p + 1;
  std::vector<double> k(size_t(m + 1));
  const int interior = n - p;  // number of interior knots
  for (int i = 0; i <= m; ++i) {
    if (i <= p)
      k[size_t(i)] = 0;
    else if (i >= m - p)
      k[size_t(i)] = 1;
    else
      k[size_t(i)] = double(i - p) / double(interior + 1);
  }
  return k;
}

std::vector<double> uniform_knots(int num_ctrl, int p) {
  const int m = num_ctrl + p;
  std::vector<double> k(size_t(m + 1));
  for (int i = 0; i <= m; ++i) k[size_t(i)] = double(i - p) / double(num_ctrl - p);
  return k;
}

std::string knot_vector_problem(std::span<const double> knots, int num_ctrl, int p) {
  const size_t need = size_t(num_ctrl + p + 1);
  if (knots.size() != need)
    return "needs " + std::to_string(need) +
           " knots (control points + degree + 1 = " + std::to_string(num_ctrl) + " + " +
           std::to_string(p) + " + 1), got " + std::to_string(knots.size());
  for (size_t i = 1; i < knots.size(); ++i)
    if (knots[i] < knots[i - 1])
      return "knots must be non-decreasing (knot " + std::to_string(i) + " is smaller than knot " +
             std::to_string(i - 1) + ")";
  const double lo = knots[size_t(p)], hi = knots[size_t(num_ctrl)];
  if (!(lo < hi))
    return "the valid domain [knot p, knot n+1] = [knot " + std::to_string(p) + ", knot " +
           std::to_string(num_ctrl) + "] is empty";
  // Inside the domain a knot repeated more than p times would tear the surface apart.
  for (size_t i = 0; i < knots.size();) {
    size_t j = i;
    while (j < knots.size() && knots[j] == knots[i]) ++j;
    if (knots[i] > lo && knots[i]<hi&& int(j - i)> p)
      return "interior knot " + std::to_string(knots[i]) + " is repeated " + std::to_string(j - i) +
             " times; at most the degree (" + std::to_string(p) + ") is allowed";
    i = j;
  }
  return {};
}

}  // namespace anamorph::spline
