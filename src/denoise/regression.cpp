#include "denoise/regression.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "denoise/lanes.h"
#include "denoise/least_squares.h"
#include "math/parallel.h"
#include "math/simd.h"

namespace anamorph::nfor {

namespace {

// Sums over a window run in 16 independent lanes (lanes.h), each in entry order, and the lanes
// are added up in order at the end: every sum has the same order on every ISA. Columns are
// handled in blocks of 4 × 4 pairs, whose 16 sums stay in registers while each entry is loaded
// once per block (not once per pair).
constexpr int kBlock = 4;
int round_up(int n, int m) { return (n + m - 1) / m * m; }

// The lanes' partial sums of Σ w_i a_i b_i for the pairs of columns a in [a0, a0 + 4) and b in
// [b0, b0 + 4) (columns `stride` apart), into part[(a·row + b)·16 + lane].
[[gnu::always_inline]] inline void block_sums(int n, int stride, const float* __restrict cols,
                                              const float* __restrict w, int a0, int b0, int row,
                                              float* __restrict part) {
  Lanes acc[kBlock][kBlock] = {};
  const float* xa = cols + size_t(a0) * stride;
  const float* xb = cols + size_t(b0) * stride;
  for (int i = 0; i < n; i += kLanes) {
    Lanes wi, wa[kBlock];
    load(wi, w + i);
#pragma GCC unroll 4
    for (int r = 0; r < kBlock; ++r) {
      load(wa[r], xa + r * stride + i);
      wa[r] *= wi;
    }
#pragma GCC unroll 4
    for (int c = 0; c < kBlock; ++c) {
      Lanes xc;
      load(xc, xb + c * stride + i);
#pragma GCC unroll 4
      for (int r = 0; r < kBlock; ++r) acc[r][c] += wa[r] * xc;
    }
  }
  for (int r = 0; r < kBlock; ++r)
    for (int c = 0; c < kBlock; ++c) store(part + ((a0 + r) * row + b0 + c) * kLanes, acc[r][c]);
}

// XᵀWX (lower triangle, p × p) and XᵀWY (p × 3) of one window as lane partial sums: cols holds
// the p columns of X, then the 3 of Y, then zero columns up to a multiple of 4, `stride`
// entries each. Blocks with no pair needed (all above the diagonal of XᵀWX) are skipped.
ANAMORPH_KERNEL_BODY void normal_equations_body(int p, int stride, const float* __restrict cols,
                                                const float* __restrict w, float* __restrict part) {
  const int row = round_up(p + 3, kBlock);
  for (int a0 = 0; a0 < p; a0 += kBlock)
    for (int b0 = 0; b0 < row; b0 += kBlock)
      if (b0 <= a0 + kBlock - 1 || b0 + kBlock - 1 >= p)
        block_sums(stride, stride, cols, w, a0, b0, row, part);
}
constexpr simd::Kernel<normal_equations_body> normal_equations;

// Each sum from its lane partial sums, in lane order.
void add_up_partials(int p, const float* part, double* m, double* rhs) {
  const int row = round_up(p + 3, kBlock);
  const auto sum = [&](int a, int b) {
    const float* v = part + (a * row + b) * kLanes;
    float s = v[0];
    for (int l = 1; l < kLanes; ++l) s += v[l];
    return double(s);
  };
  for (int a = 0; a < p; ++a) {
    for (int b = 0; b <= a; ++b) m[a * p + b] = sum(a, b);
    for (int c = 0; c < 3; ++c) rhs[a * 3 + c] = sum(a, p + c);
  }
}

// pred_c = X beta_c for every entry of the window.
ANAMORPH_KERNEL_BODY void predict_body(int p, int stride, const float* __restrict x,
                                       const float* __restrict beta, float* __restrict pred) {
  for (int c = 0; c < 3; ++c) {
    float* o = pred + c * stride;
    for (int i = 0; i < stride; ++i) o[i] = x[i] * beta[c];
    for (int a = 1; a < p; ++a)
      for (int i = 0; i < stride; ++i) o[i] += x[a * stride + i] * beta[a * 3 + c];
  }
}
constexpr simd::Kernel<predict_body> predict;

ANAMORPH_KERNEL_BODY void scatter_row_body(int n, const float* __restrict w,
                                           const float* __restrict p0, const float* __restrict p1,
                                           const float* __restrict p2, float* __restrict a0,
                                           float* __restrict a1, float* __restrict a2,
                                           float* __restrict aw) {
  for (int i = 0; i < n; ++i) {
    a0[i] += w[i] * p0[i];
    a1[i] += w[i] * p1[i];
    a2[i] += w[i] * p2[i];
    aw[i] += w[i];
  }
}
constexpr simd::Kernel<scatter_row_body> scatter_row;

// One window's columns over its (2R+1)² pixels, rounded up to whole lanes (the extra entries
// have weight 0): in `cols`, the p columns of X (1, the offsets / R, the feature differences),
// the 3 of the colour Y and zero columns up to a multiple of 4 (normal_equations); the patch
// distances d and the neighbours' coverage (which give the weights w at each bandwidth); and
// the predictions.
struct Window {
  Window(int radius, int features, MemoryMeter* meter)
      : radius(radius),
        side(2 * radius + 1),
        p(3 + features),
        stride(round_up(side * side, kLanes)),
        cols(size_t(round_up(p + 3, kBlock)) * stride, meter),
        d(size_t(stride), meter),
        cover(size_t(stride), meter),
        w(size_t(stride), meter),
        pred(3 * size_t(stride), meter) {
    for (int n = 0; n < side * side; ++n) {
      cols[n] = 1.0f;
      cols[stride + n] = float(n % side - radius) / float(radius);
      cols[2 * size_t(stride) + n] = float(n / side - radius) / float(radius);
    }
  }
  static size_t bytes(int radius, int features) {
    const int p = 3 + features;
    const size_t stride = size_t(round_up((2 * radius + 1) * (2 * radius + 1), kLanes));
    return sizeof(float) * stride * (size_t(round_up(p + 3, kBlock)) + 6);
  }
  float* col(int a) { return cols.data() + size_t(a) * stride; }
  float* y(int c) { return col(p + c); }
  int radius, side, p, stride;
  MeteredFloats cols, d, cover, w, pred;
};

struct TileScratch {
  TileScratch(const RegressionInput& in, int tile, MemoryMeter* meter)
      : patch(tile, in.patch_radius, meter),
        distances(size_t(2 * in.window_radius + 1) * (2 * in.window_radius + 1) * tile * tile,
                  meter),
        window(in.window_radius, in.features->channels(), meter) {}
  PatchScratch patch;
  MeteredFloats distances;  // per window offset (row-major), the tile's centres (row-major)
  Window window;
};

// Fills the window around c: distances, coverage, colours and feature differences (coverage and
// everything else 0 outside the image).
void gather(const RegressionInput& in, int cx, int cy, const float* distances, size_t area,
            Window& win) {
  const Planes &color = *in.color, &f = *in.features, &cov = *in.guide.coverage;
  const int width = color.width(), height = color.height(), r = win.radius, side = win.side;
  for (int oy = -r; oy <= r; ++oy) {
    const int n0 = (oy + r) * side, jy = cy + oy;
    const bool row_inside = jy >= 0 && jy < height;
    // Window columns [lo, hi) of this row are inside the image.
    const int lo = row_inside ? std::max(0, r - cx) : side;
    const int hi = row_inside ? std::max(lo, std::min(side, width - cx + r)) : side;
    const auto zero_outside = [&](float* column) {
      std::fill(column + n0, column + n0 + lo, 0.0f);
      std::fill(column + n0 + hi, column + n0 + side, 0.0f);
    };
    zero_outside(win.cover.data());
    zero_outside(win.d.data());
    for (int c = 0; c < 3; ++c) zero_outside(win.y(c));
    for (int a = 0; a < f.channels(); ++a) zero_outside(win.col(3 + a));
    if (lo >= hi) continue;
    const size_t j0 = size_t(jy) * width + size_t(cx - r + lo);
    const int n = hi - lo;
    for (int i = 0; i < n; ++i) win.d[n0 + lo + i] = distances[size_t(n0 + lo + i) * area];
    std::copy_n(cov.plane(0) + j0, n, win.cover.data() + n0 + lo);
    for (int c = 0; c < 3; ++c) std::copy_n(color.plane(c) + j0, n, win.y(c) + n0 + lo);
    for (int a = 0; a < f.channels(); ++a) {
      const float* src = f.plane(a) + j0;
      const float centre = f.at(a, cx, cy);
      float* dst = win.col(3 + a) + n0 + lo;
      for (int i = 0; i < n; ++i) dst[i] = src[i] - centre;
    }
  }
}

// The scale of each column of a window's fit: 1 / its weighted standard deviation (from XᵀWX:
// E[x²] - E[x]²), 0 for a column constant to 1e-5 of `magnitude` (the intercept keeps 1).
void column_scales(int p, const double* m, const float* magnitude, double* scale) {
  scale[0] = 1.0;
  for (int a = 1; a < p; ++a) {
    const double mean = m[a * p] / m[0], var = m[a * p + a] / m[0] - mean * mean;
    const double tol = 1e-5 * std::max(1.0, double(magnitude[a]));
    scale[a] = var > tol * tol ? 1.0 / std::sqrt(var) : 0.0;
  }
}

// The fit's coefficients (p × 3) with the window's current weights, or the weighted mean when
// the solve fails (ridge 0 only).
void fit(const RegressionInput& in, int cx, int cy, Window& win, float* beta) {
  const int p = win.p;
  constexpr int kMaxRow = (kMaxUnknowns + 3 + kBlock - 1) / kBlock * kBlock;
  alignas(64) float part[kMaxRow * kMaxRow * kLanes];
  normal_equations(p, win.stride, win.cols.data(), win.w.data(), part);
  double m[kMaxUnknowns * kMaxUnknowns], rhs[kMaxUnknowns * 3], bd[kMaxUnknowns * 3];
  add_up_partials(p, part, m, rhs);
  const double weight_sum = m[0], mean[3] = {rhs[0], rhs[1], rhs[2]};
  double scale[kMaxUnknowns];
  float magnitude[kMaxUnknowns] = {1.0f, 1.0f, 1.0f};
  for (int a = 3; a < p; ++a) magnitude[a] = std::fabs(in.features->at(a - 3, cx, cy));
  column_scales(p, m, magnitude, scale);
  // The fit in standardized columns (x_a · scale_a), so that the ridge treats them alike; a
  // column that drops out (scale 0) gets the equation beta_a = 0.
  for (int a = 0; a < p; ++a) {
    for (int b = 0; b <= a; ++b) m[a * p + b] *= scale[a] * scale[b];
    for (int c = 0; c < 3; ++c) rhs[a * 3 + c] *= scale[a];
    if (scale[a] == 0.0) m[a * p + a] = weight_sum;
  }
  std::fill_n(beta, p * 3, 0.0f);
  if (solve_ridge(p, m, rhs, 3, in.ridge, bd)) {
    for (int a = 0; a < p; ++a)
      for (int c = 0; c < 3; ++c) beta[a * 3 + c] = float(bd[a * 3 + c] * scale[a]);
  } else if (weight_sum > 0.0) {
    for (int c = 0; c < 3; ++c) beta[c] = float(mean[c] / weight_sum);
  }
}

// Fits the window with the weights of bandwidth k and adds its weighted predictions to the
// accumulator (4 planes: rgb, weight).
void fit_and_scatter(const RegressionInput& in, int cx, int cy, float k, Window& win, Planes& acc) {
  weights_from_distances(win.stride, win.d.data(), k, win.cover.data(), win.w.data());
  float beta[kMaxUnknowns * 3];
  fit(in, cx, cy, win, beta);
  predict(win.p, win.stride, win.cols.data(), beta, win.pred.data());
  const int width = acc.width(), height = acc.height(), r = win.radius;
  for (int oy = -r; oy <= r; ++oy) {
    const int jy = cy + oy;
    if (jy < 0 || jy >= height) continue;
    const int xa = std::max(cx - r, 0), xb = std::min(cx + r + 1, width);
    const size_t n = size_t(oy + r) * win.side + (xa - (cx - r)), j = size_t(jy) * width + xa;
    const size_t s = size_t(win.stride);
    scatter_row(xb - xa, win.w.data() + n, win.pred.data() + n, win.pred.data() + s + n,
                win.pred.data() + 2 * s + n, acc.plane(0) + j, acc.plane(1) + j, acc.plane(2) + j,
                acc.plane(3) + j);
  }
}

void regress_tile(const RegressionInput& in, const Rect& r, TileScratch& s,
                  std::vector<Planes>& acc) {
  const int radius = in.window_radius;
  const size_t area = r.area();
  for (int dy = -radius, o = 0; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx, ++o)
      patch_distances(in.guide, in.patch_radius, r, dx, dy, s.patch,
                      s.distances.data() + size_t(o) * area);
  const Planes& cov = *in.guide.coverage;
  for (int y = r.y0; y < r.y1; ++y)
    for (int x = r.x0; x < r.x1; ++x) {
      if (!(cov.at(0, x, y) > 0.0f)) continue;
      const size_t centre = size_t(y - r.y0) * r.width() + (x - r.x0);
      gather(in, x, y, s.distances.data() + centre, area, s.window);
      for (size_t k = 0; k < in.bandwidths.size(); ++k)
        fit_and_scatter(in, x, y, in.bandwidths[k], s.window, acc[k]);
    }
}

}  // namespace

void collaborative_regression(const RegressionInput& in, std::span<Planes* const> out,
                              MemoryMeter* meter, const std::atomic<bool>* cancel) {
  check_guide(in.guide);
  const int width = in.color->width(), height = in.color->height();
  const int tile = tile_size_for(in.window_radius);
  const TileLayout tiles(width, height, tile);
  std::vector<Planes> acc;
  for (size_t k = 0; k < in.bandwidths.size(); ++k) acc.emplace_back(width, height, 4, meter);
  for (int phase = 0; phase < 4; ++phase) {
    std::vector<size_t> mine;
    for (size_t t = 0; t < tiles.count(); ++t)
      if (int(t % tiles.cols) % 2 == phase % 2 && int(t / tiles.cols) % 2 == phase / 2)
        mine.push_back(t);
    parallel_chunks(0, mine.size(), 1, [&](size_t lo, size_t hi) {
      if (cancel && cancel->load()) return;
      TileScratch scratch(in, tile, meter);
      for (size_t i = lo; i < hi; ++i) regress_tile(in, tiles.rect(mine[i]), scratch, acc);
    });
  }
  const size_t n = size_t(width) * size_t(height);
  for (size_t k = 0; k < acc.size(); ++k)
    for (int c = 0; c < 3; ++c)
      for (size_t i = 0; i < n; ++i) {
        const float w = acc[k].plane(3)[i];
        out[k]->plane(c)[i] = w > 0.0f ? acc[k].plane(c)[i] / w : 0.0f;
      }
}

size_t regression_scratch_bytes(int window_radius, int patch_radius, int features) {
  const int tile = tile_size_for(window_radius);
  const size_t offsets = size_t(2 * window_radius + 1) * (2 * window_radius + 1);
  return PatchScratch::bytes(tile, patch_radius) + sizeof(float) * offsets * tile * tile +
         Window::bytes(window_radius, features);
}

}  // namespace anamorph::nfor
