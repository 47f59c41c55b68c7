#include "camera/spline_surface.h"

#include <atomic>
#include <bit>
#include <cmath>

#include "math/simd.h"

namespace anamorph {

namespace {

uint64_t next_surface_id() {
  static std::atomic<uint64_t> next{1};
  return next.fetch_add(1, std::memory_order_relaxed);
}

// A direct-mapped per-thread cache of basis functions (degree <= 3) by surface and parameter.
struct CachedBasis {
  uint64_t owner = 0, key = 0;  // surface id, bits of the parameter
  int span = 0;
  double d[3][4];
};
constexpr size_t kCacheSlots = 64;
struct BasisCache {
  CachedBasis u[kCacheSlots], v[kCacheSlots];
};
thread_local BasisCache t_bases;

// Rows in power form (SplineSurface::row_poly) by surface, parameter t and s-span: the packets
// along a tile row (8 for the default 32-pixel tiles) repeat their four rows, and the next tile
// of a row of tiles repeats all of them.
struct CachedRow {
  uint64_t owner = 0, key = 0;
  int span = -1;
  double c[3][4][4];
};
constexpr int kRowBits = 8;  // 256 rows, 100 KB per thread
constexpr size_t kRowSlots = size_t(1) << kRowBits;
thread_local CachedRow t_rows[kRowSlots];

// A slot among 2^bits from a hash of the key and the owner.
size_t cache_slot(uint64_t key, uint64_t owner, int bits = 6) {
  uint64_t h = key ^ (owner * 0x9E3779B97F4A7C15ull);
  h ^= h >> 31;
  h *= 0xBF58476D1CE4E5B9ull;
  return size_t(h >> (64 - bits));  // the top bits
}

}  // namespace

SplineSurface::SplineSurface(SplineNet net, int p, int q, Basis basis, std::vector<double> knots_u,
                             std::vector<double> knots_v)
    : nu_(net.nu),
      nv_(net.nv),
      p_(p),
      q_(q),
      basis_(basis),
      rational_(!net.weights.empty()),
      ku_(std::move(knots_u)),
      kv_(std::move(knots_v)),
      id_(next_surface_id()) {
  ctrl_.resize(4 * net.points.size());
  Bounds3 box;
  for (size_t k = 0; k < net.points.size(); ++k) {
    const double w = rational_ ? net.weights[k] : 1.0;
    const Vec3 hp = net.points[k] * w;
    ctrl_[4 * k] = hp.x, ctrl_[4 * k + 1] = hp.y, ctrl_[4 * k + 2] = hp.z, ctrl_[4 * k + 3] = w;
    box.extend(net.points[k]);
  }
  size_ = std::max(length(box.diagonal()), 1e-300);
  if (basis_ == Basis::BSpline) {
    s_lo_ = ku_[size_t(p_)];
    s_hi_ = ku_[size_t(nu_)];
    t_lo_ = kv_[size_t(q_)];
    t_hi_ = kv_[size_t(nv_)];
  }
  if (p_ <= 3) {
    // Each span's basis functions as cubics in h = s - start: value, slope and half the second
    // derivative at the start, the cubic term from the second derivative at the end.
    const int spans = basis_ == Basis::BSpline ? nu_ : p_ + 1;
    to_power_.assign(16 * size_t(spans), 0.0);
    for (int i = p_; i < spans; ++i) {
      spline::BasisDers d0, d1;
      double w = 1;
      if (basis_ == Basis::Bernstein) {
        spline::bernstein_ders(p_, 0, d0);
        spline::bernstein_ders(p_, 1, d1);
      } else {
        w = ku_[size_t(i) + 1] - ku_[size_t(i)];
        if (!(w > 0)) continue;  // an empty span: find_span never returns it
        spline::ders_basis_funs(i, ku_[size_t(i)], p_, 2, ku_, d0);
        spline::ders_basis_funs(i, ku_[size_t(i) + 1], p_, 2, ku_, d1);
      }
      for (int l = 0; l <= p_; ++l) {
        double* c = &to_power_[16 * size_t(i) + 4 * size_t(l)];
        c[0] = d0[0][l], c[1] = d0[1][l], c[2] = 0.5 * d0[2][l];
        c[3] = p_ == 3 ? (d1[2][l] - d0[2][l]) / (6 * w) : 0.0;
      }
    }
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

void SplineSurface::cached_basis(bool along_u, double x, Basis1* b) const {
  const int deg = along_u ? p_ : q_;
  if (deg > 3) return along_u ? basis_u(x, b) : basis_v(x, b);
  const uint64_t key = std::bit_cast<uint64_t>(x);
  CachedBasis& c = (along_u ? t_bases.u : t_bases.v)[cache_slot(key, id_)];
  if (c.owner == id_ && c.key == key) {
    b->span = c.span;
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i <= deg; ++i) b->d[k][i] = c.d[k][i];
    return;
  }
  along_u ? basis_u(x, b) : basis_v(x, b);
  c.owner = id_, c.key = key, c.span = b->span;
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i <= deg; ++i) c.d[k][i] = b->d[k][i];
}

template <bool Rational>
void SplineSurface::columns_impl(const Basis1& bv, int first_col, Columns& q) const {
  const int first_row = bv.span - q_;
  const size_t stride = 4 * size_t(nu_);
  for (int l = 0; l <= p_; ++l) {
    double acc[3][4] = {};
    const double* c = &ctrl_[4 * (size_t(first_row) * size_t(nu_) + size_t(first_col + l))];
    for (int k = 0; k <= q_; ++k, c += stride)
      for (int o = 0; o < 3; ++o) {
        const double b = bv.d[o][k];
        acc[o][0] += c[0] * b;
        acc[o][1] += c[1] * b;
        acc[o][2] += c[2] * b;
        if constexpr (Rational) acc[o][3] += c[3] * b;
      }
    for (int o = 0; o < 3; ++o)
      for (int x = 0; x < 4; ++x) q.c[l][o][x] = acc[o][x];
  }
}

void SplineSurface::columns(const Basis1& bv, int first_col, Columns& q) const {
  if (rational_)
    columns_impl<true>(bv, first_col, q);
  else
    columns_impl<false>(bv, first_col, q);
}

template <bool Rational>
LocalGeom SplineSurface::combine_impl(const Basis1& bu, const Columns& q) const {
  // a[d][x]: derivative d in {00, 10, 01, 20, 11, 02} (s-order, t-order) of A = sum (w P, w).
  double a[6][4] = {};
  for (int l = 0; l <= p_; ++l) {
    const double n0 = bu.d[0][l], n1 = bu.d[1][l], n2 = bu.d[2][l];
    const auto& c = q.c[l];
    for (int x = 0; x < (Rational ? 4 : 3); ++x) {
      a[0][x] += c[0][x] * n0;
      a[1][x] += c[0][x] * n1;
      a[2][x] += c[1][x] * n0;
      a[3][x] += c[0][x] * n2;
      a[4][x] += c[1][x] * n1;
      a[5][x] += c[2][x] * n0;
    }
  }
  const auto v = [&](int d) { return Vec3{a[d][0], a[d][1], a[d][2]}; };
  if constexpr (!Rational) {
    return {v(0), v(1), v(2), v(3), v(4), v(5)};
  } else {
    // Quotient rule for S = A / W up to second order.
    const double iw = 1.0 / a[0][3];
    const double ws = a[1][3], wt = a[2][3], wss = a[3][3], wst = a[4][3], wtt = a[5][3];
    LocalGeom g;
    g.p = v(0) * iw;
    g.ps = (v(1) - g.p * ws) * iw;
    g.pt = (v(2) - g.p * wt) * iw;
    g.pss = (v(3) - g.ps * (2 * ws) - g.p * wss) * iw;
    g.pst = (v(4) - g.ps * wt - g.pt * ws - g.p * wst) * iw;
    g.ptt = (v(5) - g.pt * (2 * wt) - g.p * wtt) * iw;
    return g;
  }
}

LocalGeom SplineSurface::combine(const Basis1& bu, const Columns& q) const {
  return rational_ ? combine_impl<true>(bu, q) : combine_impl<false>(bu, q);
}

void SplineSurface::row_poly(const Basis1& bv, int span_u, RowPoly& c) const {
  Columns q;
  columns(bv, span_u - p_, q);
  const double* m = &to_power_[16 * size_t(span_u)];
  for (int o = 0; o < 3; ++o)
    for (int e = 0; e < 4; ++e)
      for (int x = 0; x < 4; ++x) {
        double acc = 0;
        for (int l = 0; l <= p_; ++l) acc += m[4 * l + e] * q.c[l][o][x];
        c[o][e][x] = acc;
      }
}

namespace {

// Lanes a .. a+m-1 of one row and span from its power form: Horner in h for A, dA/ds, d2A/ds2
// (o = 0), dA/dt, d2A/dsdt (o = 1) and d2A/dt2 (o = 2), then the quotient rule if rational.
template <bool kRational>
[[gnu::always_inline]] inline void row_lanes(const double (&rc)[3][4][4],
                                             const double* __restrict h, int a, int m,
                                             LocalGeomBatch* __restrict out) {
  double c[3][4][4];  // a local copy: stores to `out` cannot alias it
  for (int o = 0; o < 3; ++o)
    for (int e = 0; e < 4; ++e)
      for (int x = 0; x < 4; ++x) c[o][e][x] = rc[o][e][x];
  for (int j = 0; j < m; ++j) {
    const double t = h[j];
    double A[6][4];
    for (int x = 0; x < (kRational ? 4 : 3); ++x) {
      A[0][x] = ((c[0][3][x] * t + c[0][2][x]) * t + c[0][1][x]) * t + c[0][0][x];
      A[1][x] = (3 * c[0][3][x] * t + 2 * c[0][2][x]) * t + c[0][1][x];
      A[2][x] = ((c[1][3][x] * t + c[1][2][x]) * t + c[1][1][x]) * t + c[1][0][x];
      A[3][x] = 6 * c[0][3][x] * t + 2 * c[0][2][x];
      A[4][x] = (3 * c[1][3][x] * t + 2 * c[1][2][x]) * t + c[1][1][x];
      A[5][x] = ((c[2][3][x] * t + c[2][2][x]) * t + c[2][1][x]) * t + c[2][0][x];
    }
    const int i = a + j;
    if constexpr (!kRational) {
      for (int x = 0; x < 3; ++x) {
        out->p[x][i] = A[0][x], out->ps[x][i] = A[1][x], out->pt[x][i] = A[2][x];
        out->pss[x][i] = A[3][x], out->pst[x][i] = A[4][x], out->ptt[x][i] = A[5][x];
      }
    } else {
      // Quotient rule for S = A / W up to second order (as combine_impl).
      const double iw = 1.0 / A[0][3];
      const double ws = A[1][3], wt = A[2][3], wss = A[3][3], wst = A[4][3], wtt = A[5][3];
      for (int x = 0; x < 3; ++x) {
        const double p = A[0][x] * iw;
        const double ps = (A[1][x] - p * ws) * iw, pt = (A[2][x] - p * wt) * iw;
        out->p[x][i] = p, out->ps[x][i] = ps, out->pt[x][i] = pt;
        out->pss[x][i] = (A[3][x] - ps * (2 * ws) - p * wss) * iw;
        out->pst[x][i] = (A[4][x] - ps * wt - pt * ws - p * wst) * iw;
        out->ptt[x][i] = (A[5][x] - pt * (2 * wt) - p * wtt) * iw;
      }
    }
  }
}

ANAMORPH_KERNEL_BODY void row_lanes_clones_body(const double (&c)[3][4][4], bool rational,
                                                const double* h, int a, int m,
                                                LocalGeomBatch* out) {
  // A 4x4 packet of pixel centers has rows of 4 lanes.
  with_trip_count<4>(
      m, [&](auto k) __attribute__((always_inline)) {
        if (rational)
          row_lanes<true>(c, h, a, k, out);
        else
          row_lanes<false>(c, h, a, k, out);
      });
}
constexpr simd::Kernel<row_lanes_clones_body> row_lanes_clones;

}  // namespace

void SplineSurface::polynomial_rows(const double* ss, const double* ts, int n,
                                    LocalGeomBatch* out) const {
  constexpr int kMax = kCameraBatch;
  double h[kMax];
  int span[kMax];
  for (int k = 0; k < n; ++k) {
    // (A 4x4 packet repeats each s four lanes later.)
    const int same = k >= 4 && ss[k] == ss[k - 4]   ? k - 4
                     : k >= 1 && ss[k] == ss[k - 1] ? k - 1
                                                    : -1;
    if (same >= 0) {
      span[k] = span[same], h[k] = h[same];
    } else if (basis_ == Basis::Bernstein) {
      span[k] = p_, h[k] = ss[k];
    } else {
      span[k] = spline::find_span(nu_ - 1, p_, ss[k], ku_);
      h[k] = std::clamp(ss[k], s_lo_, s_hi_) - ku_[size_t(span[k])];
    }
  }
  for (int a = 0; a < n;) {
    int b = a + 1;
    while (b < n && ts[b] == ts[a] && span[b] == span[a]) ++b;
    const uint64_t key = std::bit_cast<uint64_t>(ts[a]);
    CachedRow& c = t_rows[cache_slot(key + uint64_t(span[a]), id_, kRowBits)];
    if (!(c.owner == id_ && c.key == key && c.span == span[a])) {
      Basis1 bv;
      basis_v(ts[a], &bv);  // (the row cache stands in for the basis cache here)
      row_poly(bv, span[a], c.c);
      c.owner = id_, c.key = key, c.span = span[a];
    }
    row_lanes_clones(c.c, rational_, h + a, a, b - a, out);
    a = b;
  }
}

void SplineSurface::eval_batch(const double* ss, const double* ts, int n,
                               LocalGeomBatch* out) const {
  if (!to_power_.empty())
    polynomial_rows(ss, ts, n, out);
  else
    for_batch(ss, ts, n, [&](int k, const LocalGeom& g) { out->set(k, g); });
}

}  // namespace anamorph
