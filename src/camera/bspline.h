// B-spline and Bernstein basis functions with derivatives (The NURBS Book, Piegl & Tiller:
// A2.1 find_span, A2.2 basis_funs, A2.3 ders_basis_funs), and knot vector construction and
// validation. Evaluation writes into caller-provided fixed-size arrays: no allocation.
#pragma once

#include <span>
#include <string>
#include <vector>

namespace anamorph::spline {

inline constexpr int kMaxDegree = 15;  // B-spline / NURBS degree cap (stack array size)
inline constexpr int kMaxBezierDegree = 31;
inline constexpr int kMaxDerivative = 2;

// Rows of basis values: ders[k][j] = k-th derivative of the j-th non-zero basis function (one
// array type for both bases, sized for the larger Bezier cap).
using BasisDers = double[kMaxDerivative + 1][kMaxBezierDegree + 1];

// The knot span index i with knots[i] <= t < knots[i+1], for t clamped into the valid domain
// [knots[p], knots[n+1]] (n = last control point index); t at the domain's end maps to the last
// non-empty span.
int find_span(int n, int p, double t, std::span<const double> knots);

// The p+1 non-zero basis functions N[span-p .. span] at t (A2.2).
void basis_funs(int span, double t, int p, std::span<const double> knots, double* out);

// Basis functions and their derivatives up to order nd <= 2 at t (A2.3).
void ders_basis_funs(int span, double t, int p, int nd, std::span<const double> knots,
                     BasisDers& ders);

// Bernstein polynomials B_{i,p}(t), i = 0..p, and their first two derivatives.
void bernstein_ders(int p, double t, BasisDers& ders);

// Open uniform (clamped) knots on [0, 1]: p+1 zeros, evenly spaced interior knots, p+1 ones.
std::vector<double> clamped_knots(int num_ctrl, int p);
// Uniform (unclamped) knots, spaced 1 / (num_ctrl - p) so that the valid domain is [0, 1].
std::vector<double> uniform_knots(int num_ctrl, int p);

// Empty if the knot vector is usable for num_ctrl control points of degree p, else the reason:
// wrong length, decreasing, an empty domain, or an interior knot repeated more than p times.
std::string knot_vector_problem(std::span<const double> knots, int num_ctrl, int p);

}  // namespace anamorph::spline
