// Tensor-product spline surfaces (B-spline, NURBS, Bezier) in their own parameters, with first
// and second derivatives. All setup happens in the constructor; evaluation uses fixed-size stack
// arrays only. A row of samples shares its v-basis, a run of samples in one knot span shares the
// column sums, which is what makes a packet cheaper than separate evaluations.
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "camera/bspline.h"
#include "camera/org_common.h"

namespace anamorph {

// A control net: nu points per row (along u, left to right), nv rows (along v, top to bottom).
struct SplineNet {
  int nu = 0, nv = 0;
  std::vector<Vec3> points;     // row-major: points[j * nu + i]
  std::vector<double> weights;  // same layout; empty = non-rational (all weights 1)
};

class SplineSurface {
 public:
  enum class Basis { BSpline, Bernstein };

  // For Basis::BSpline the knot vectors must be valid (spline::knot_vector_problem); for
  // Basis::Bernstein p = nu - 1, q = nv - 1 and the knots are ignored.
  SplineSurface(SplineNet net, int p, int q, Basis basis, std::vector<double> knots_u = {},
                std::vector<double> knots_v = {});

  // The valid parameter domain.
  double s_lo() const { return s_lo_; }
  double s_hi() const { return s_hi_; }
  double t_lo() const { return t_lo_; }
  double t_hi() const { return t_hi_; }
  // A length scale of the net (its bounding box diagonal), for degeneracy tests.
  double size() const { return size_; }

  LocalGeom eval(double s, double t) const {
    Basis1 bu, bv;
    basis_u(s, &bu);
    basis_v(t, &bv);
    Columns q;
    columns(bv, bu.span - p_, q);
    return combine(bu, q);
  }

  // The n <= kCameraBatch pairs (ss[k], ts[k]) into lanes of `out`. Degrees up to 3 along s take
  // each row's curve in power form per knot span (polynomial_rows), others for_batch.
  void eval_batch(const double* ss, const double* ts, int n, LocalGeomBatch* out) const;

  // Calls emit(k, geom) for the n <= 16 pairs (ss[k], ts[k]), each distinct s's and t's basis
  // computed once: a packet of pixel centers (4x4, row by row) has four of each, and a row
  // shares its column sums. The same arithmetic as eval(), so the same bits.
  template <class Emit>
  void for_batch(const double* ss, const double* ts, int n, Emit&& emit) const {
    constexpr int kMax = 16;
    Basis1 bu[kMax], bv[kMax];
    int iu[kMax], iv[kMax], nu = 0, nv = 0;
    const auto index_of = [](const double* seen, int count, double x) {
      for (int j = count - 1; j >= 0; --j)
        if (seen[j] == x) return j;
      return -1;
    };
    double su[kMax], sv[kMax];
    for (int k = 0; k < n; ++k) {
      int j = index_of(su, nu, ss[k]);
      if (j < 0) su[j = nu++] = ss[k], cached_basis(true, ss[k], &bu[j]);
      iu[k] = j;
      j = index_of(sv, nv, ts[k]);
      if (j < 0) sv[j = nv++] = ts[k], cached_basis(false, ts[k], &bv[j]);
      iv[k] = j;
    }
    Columns q;
    int cached_v = -1, cached_span = -1;
    for (int k = 0; k < n; ++k) {
      const Basis1& b = bu[iu[k]];
      if (iv[k] != cached_v || b.span != cached_span) {
        columns(bv[iv[k]], b.span - p_, q);
        cached_v = iv[k], cached_span = b.span;
      }
      emit(k, combine(b, q));
    }
  }

 private:
  // Non-zero basis functions at one parameter: derivatives 0..2 of N[span - degree .. span].
  // Plain arrays without initializers: nothing is zeroed per evaluation.
  struct Basis1 {
    int span;
    spline::BasisDers d;
  };
  // Column sums: c[l][k] is the k-th t-derivative of sum_j M_j(t) (w P, w)_{first_col + l, j}.
  struct Columns {
    double c[spline::kMaxBezierDegree + 1][3][4];
  };

  void basis_u(double s, Basis1* b) const;
  void basis_v(double t, Basis1* b) const;
  // basis_u / basis_v through a small per-thread cache (degrees up to 3): the renderer's
  // packets walk a tile row by row, so a row of packets repeats its t values and the next row
  // repeats the columns' s values. The same bits as computing them.
  void cached_basis(bool along_u, double x, Basis1* b) const;
  void columns(const Basis1& bv, int first_col, Columns& q) const;
  LocalGeom combine(const Basis1& bu, const Columns& q) const;
  template <bool Rational>
  void columns_impl(const Basis1& bv, int first_col, Columns& q) const;
  template <bool Rational>
  LocalGeom combine_impl(const Basis1& bu, const Columns& q) const;

  // Power form of a row: c[o][e][x] is the h^e coefficient of the o-th t-derivative of A,
  // h = s - (start of the s-span). Runs of lanes with one row and span share it.
  using RowPoly = double[3][4][4];
  void row_poly(const Basis1& bv, int span_u, RowPoly& c) const;
  void polynomial_rows(const double* ss, const double* ts, int n, LocalGeomBatch* out) const;

  int nu_, nv_, p_, q_;
  Basis basis_;
  bool rational_;
  std::vector<double> ctrl_;  // homogeneous (w x, w y, w z, w) per control point, row-major
  std::vector<double> ku_, kv_;
  double s_lo_ = 0, s_hi_ = 1, t_lo_ = 0, t_hi_ = 1, size_ = 1;
  uint64_t id_;  // tells this surface's cached bases from others' (copies are identical)
  // p <= 3: the s-basis functions of each span as cubics in h, to_power_[16 span + 4 l + e].
  std::vector<double> to_power_;
};

}  // namespace anamorph
