#include "camera/spline_surface.h"

#include <cmath>

namespace anamorph {

SplineSurface::SplineSurface(SplineNet net, int p, int q, Basis basis,
                             std::vector<double> knots_u, std::vector<double> knots_v)
    : nu_(net.nu),
      nv_(net.nv),
      p_(p),
      q_(q),
      basis_(basis),
      rational_(!net.weights.empty()),
      ku_(std::move(knots_u)),
      kv_(std::move(knots_v)) {
  ctrl_.resize(net.points.size());
  Bounds3 box;
  for (size_t k = 0; k < net.points.size(); ++k) {
    const double w = rational_ ? net.weights[k] : 1.0;
    ctrl_[k] = {net.points[k] * w, w};
    box.extend(net.points[k]);
  }
  size_ = std::max(length(box.diagonal()), 1e-300);
  if (basis_ == Basis::BSpline) {
    s_lo_ = ku_[size_t(p_)];
    s_hi_ = ku_[size_t(nu_)];
    t_lo_ = kv_[size_t(q_)];
    t_hi_ = kv_[size_t(nv_)];
  }
}

void SplineSurface::basis_u(double s, Basis1* b) const {
  if (basis_ == Basis::Bernstein) {
    b->span = p_;
    spline::bernstein_ders(p_, s, b->d);
  } else {
    b->span = spline::find_span(nu_ - 1, p_, s, ku_);
    spline::ders_basis_funs(b->span, std::clamp(s, s_lo_, s_hi_), p_, 2, ku_, b->d);
  }
}

void SplineSurface::basis_v(double t, Basis1* b) const {
  if (basis_ == Basis::Bernstein) {
    b->span = q_;
    spline::bernstein_ders(q_, t, b->d);
  } else {
    b->span = spline::find_span(nv_ - 1, q_, t, kv_);
    spline::ders_basis_funs(b->span, std::clamp(t, t_lo_, t_hi_), q_, 2, kv_, b->d);
  }
}

void SplineSurface::columns(const Basis1& bv, int first_col, H (*q)[3]) const {
  const int first_row = bv.span - q_;
  for (int l = 0; l <= p_; ++l) {
    H h0, h1, h2;
    const H* c = &ctrl_[size_t(first_row) * size_t(nu_) + size_t(first_col + l)];
    for (int k = 0; k <= q_; ++k, c += nu_) {
      const double b0 = bv.d[0][k], b1 = bv.d[1][k], b2 = bv.d[2][k];
      h0.a += c->a * b0;
      h1.a += c->a * b1;
      h2.a += c->a * b2;
      if (rational_) {
        h0.w += c->w * b0;
        h1.w += c->w * b1;
        h2.w += c->w * b2;
      }
    }
    q[l][0] = h0;
    q[l][1] = h1;
    q[l][2] = h2;
  }
}

LocalGeom SplineSurface::combine(const Basis1& bu, const H (*q)[3]) const {
  // A_ab = sum_l N^(a)(s) Q^(b)(t): a-th s-derivative, b-th t-derivative.
  H a00, a10, a01, a20, a11, a02;
  for (int l = 0; l <= p_; ++l) {
    const double n0 = bu.d[0][l], n1 = bu.d[1][l], n2 = bu.d[2][l];
    a00.a += q[l][0].a * n0;
    a10.a += q[l][0].a * n1;
    a20.a += q[l][0].a * n2;
    a01.a += q[l][1].a * n0;
    a11.a += q[l][1].a * n1;
    a02.a += q[l][2].a * n0;
    if (rational_) {
      a00.w += q[l][0].w * n0;
      a10.w += q[l][0].w * n1;
      a20.w += q[l][0].w * n2;
      a01.w += q[l][1].w * n0;
      a11.w += q[l][1].w * n1;
      a02.w += q[l][2].w * n0;
    }
  }
  if (!rational_) return {a00.a, a10.a, a01.a, a20.a, a11.a, a02.a};
  // Quotient rule for S = A / W up to second order.
  const double iw = 1.0 / a00.w;
  LocalGeom g;
  g.p = a00.a * iw;
  g.ps = (a10.a - g.p * a10.w) * iw;
  g.pt = (a01.a - g.p * a01.w) * iw;
  g.pss = (a20.a - g.ps * (2 * a10.w) - g.p * a20.w) * iw;
  g.pst = (a11.a - g.ps * a01.w - g.pt * a10.w - g.p * a11.w) * iw;
  g.ptt = (a02.a - g.pt * (2 * a01.w) - g.p * a02.w) * iw;
  return g;
}

}  // namespace anamorph
