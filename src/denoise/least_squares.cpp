#include "denoise/least_squares.h"

#include <algorithm>
#include <cmath>

namespace anamorph::nfor {

// Right-looking Cholesky and column-oriented substitutions: each step's updates are independent
// of each other, so they overlap instead of waiting on one long chain of subtractions.
bool solve_ridge(int n, const double* m, const double* rhs, int nrhs, double ridge, double* beta) {
  if (n <= 0 || n > kMaxUnknowns || nrhs <= 0 || nrhs > 3) return false;
  double a[kMaxUnknowns][kMaxUnknowns];  // lower triangle: A, overwritten by L
  for (int i = 0; i < n; ++i)
    for (int j = 0; j <= i; ++j) a[i][j] = m[i * n + j] + (i == j && i > 0 ? ridge * m[0] : 0.0);
  for (int k = 0; k < n; ++k) {
    if (!(a[k][k] > 0.0)) return false;
    const double d = std::sqrt(a[k][k]);
    a[k][k] = d;
    for (int i = k + 1; i < n; ++i) a[i][k] /= d;
    for (int i = k + 1; i < n; ++i)
      for (int j = k + 1; j <= i; ++j) a[i][j] -= a[i][k] * a[j][k];
  }
  double z[kMaxUnknowns][3];
  for (int i = 0; i < n; ++i)
    for (int r = 0; r < nrhs; ++r) z[i][r] = rhs[i * nrhs + r];
  for (int k = 0; k < n; ++k) {  // L z = rhs
    for (int r = 0; r < nrhs; ++r) z[k][r] /= a[k][k];
    for (int i = k + 1; i < n; ++i)
      for (int r = 0; r < nrhs; ++r) z[i][r] -= a[i][k] * z[k][r];
  }
  for (int k = n - 1; k >= 0; --k) {  // Lᵀ beta = z
    for (int r = 0; r < nrhs; ++r) z[k][r] /= a[k][k];
    for (int i = 0; i < k; ++i)
      for (int r = 0; r < nrhs; ++r) z[i][r] -= a[k][i] * z[k][r];
  }
  for (int i = 0; i < n; ++i)
    for (int r = 0; r < nrhs; ++r) beta[i * nrhs + r] = z[i][r];
  return true;
}

}  // namespace anamorph::nfor
