// The small dense solve of the regression: the normal equations of a weighted least-squares fit
// with a ridge on the slopes, by Cholesky factorization in double precision.
#pragma once

namespace anamorph::nfor {

// Most unknowns a fit has: intercept, two pixel offsets and up to kMaxFeatureChannels features.
inline constexpr int kMaxFeatureChannels = 12;
inline constexpr int kMaxUnknowns = 3 + kMaxFeatureChannels;

// Solves (M + ridge · M[0][0] · diag(0, 1, ..., 1)) beta = rhs for beta (n × nrhs, row-major,
// nrhs <= 3), where M (n × n, row-major, symmetric; only its lower triangle is read) is XᵀWX of
// a fit whose first column is the constant 1, so M[0][0] is the sum of the weights. The ridge
// makes the system positive definite whenever M[0][0] > 0; on columns scaled to unit spread it
// shrinks the slopes by about the fraction `ridge`. Returns false (beta untouched) if a pivot
// is not positive (M[0][0] <= 0, or rounding with ridge 0 and a singular M).
bool solve_ridge(int n, const double* m, const double* rhs, int nrhs, double ridge, double* beta);

}  // namespace anamorph::nfor
