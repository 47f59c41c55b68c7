#include "denoise/nl_means.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "denoise/lanes.h"
#include "math/parallel.h"
#include "math/simd.h"

namespace anamorph::nfor {

namespace {

// Keeps the distance finite where both variances are 0 (noise-free features): there any
// difference is a real one and the weight falls to 0.
constexpr float kEps = 1e-10f;
// Pairs farther apart than this (weights below e^-80) get weight 0.
constexpr float kFar = 80.0f;
// Tile side of the pixel-wise filter (its tiles write only their own pixels).
constexpr int kFilterTile = 32;

// One channel's term of d_c(p, q) at k = 1.
[[gnu::always_inline]] inline float channel_term(float gp, float gq, float vp, float vq) {
  const float diff = gp - gq;
  return (diff * diff - (vp + std::min(vp, vq))) / (kEps + vp + vq);
}

// A row of the guide's values and variances at p and at q = p + offset, channel by channel.
struct RowPair {
  const float* gp[3];
  const float* gq[3];
  const float* vp[3];
  const float* vq[3];
};

// Keeps a pair's distance where both pixels are covered (else 0) and counts the pair (1 or 0).
// Returns how many pairs are present. (Masks in a loop of their own: mixed with the distance
// terms, the loop would not vectorize.)
[[gnu::always_inline]] inline int mask_pairs(int n, const float* __restrict cp,
                                             const float* __restrict cq, float* __restrict dist,
                                             float* __restrict count) {
  int present = 0;
  for (int i = 0; i < n; ++i) {
    const bool both = (cp[i] > 0.0f) & (cq[i] > 0.0f);
    dist[i] = both ? dist[i] : 0.0f;
    count[i] = both ? 1.0f : 0.0f;
    present += both;
  }
  return present;
}

// d(p, q) (the mean of the channels' terms) where both pixels are covered, else 0, and the pair
// counts, for n pixels of a row; returns how many pairs are present. One function per channel
// count in use: the colour (3) and a feature channel (1).
ANAMORPH_KERNEL_BODY int pair_distances3_body(int n, const RowPair& r, const float* __restrict cp,
                                              const float* __restrict cq, float* __restrict dist,
                                              float* __restrict count) {
  const float* __restrict g0 = r.gp[0], * __restrict g1 = r.gp[1], * __restrict g2 = r.gp[2];
  const float* __restrict h0 = r.gq[0], * __restrict h1 = r.gq[1], * __restrict h2 = r.gq[2];
  const float* __restrict v0 = r.vp[0], * __restrict v1 = r.vp[1], * __restrict v2 = r.vp[2];
  const float* __restrict u0 = r.vq[0], * __restrict u1 = r.vq[1], * __restrict u2 = r.vq[2];
  for (int i = 0; i < n; ++i) {
    float acc = 0.0f;
    acc += channel_term(g0[i], h0[i], v0[i], u0[i]);
    acc += channel_term(g1[i], h1[i], v1[i], u1[i]);
    acc += channel_term(g2[i], h2[i], v2[i], u2[i]);
    dist[i] = acc * (1.0f / 3.0f);
  }
  return mask_pairs(n, cp, cq, dist, count);
}
constexpr simd::Kernel<pair_distances3_body> pair_distances3;

ANAMORPH_KERNEL_BODY int pair_distances1_body(int n, const RowPair& r, const float* __restrict cp,
                                              const float* __restrict cq, float* __restrict dist,
                                              float* __restrict count) {
  const float* __restrict g0 = r.gp[0], * __restrict h0 = r.gq[0];
  const float* __restrict v0 = r.vp[0], * __restrict u0 = r.vq[0];
  for (int i = 0; i < n; ++i) dist[i] = channel_term(g0[i], h0[i], v0[i], u0[i]);
  return mask_pairs(n, cp, cq, dist, count);
}
constexpr simd::Kernel<pair_distances1_body> pair_distances1;

// e^-x for x in [0, 80] as straight-line code that vectorizes: x = k ln2 - r, e^-r by its Taylor
// polynomial to degree 7 on |r| <= ln2/2 (relative error below 2e-7), 2^-k put into the bits.
[[gnu::always_inline]] inline float exp_neg(float x) {
  constexpr float kLog2e = 1.44269504f, kLn2Hi = 0.693145752f, kLn2Lo = 1.42860677e-6f;
  constexpr float kRound = 12582912.0f;  // 1.5 * 2^23: adding and removing it rounds to integer
  const float k = (x * kLog2e + kRound) - kRound;
  const float r = (k * kLn2Hi - x) + k * kLn2Lo;  // e^-x = 2^-k e^r
  const float p =
      1.0f + r * (1.0f + r * (0.5f + r * (1.66666672e-1f +
                                          r * (4.16666679e-2f +
                                               r * (8.33333377e-3f +
                                                    r * (1.38888892e-3f + r * 1.98412701e-4f))))));
  return p * std::bit_cast<float>((127 - int32_t(k)) << 23);
}

// out[i] = in[i] + in[i + step] + ... + in[i + (taps - 1) step], in that order, for i < n: the
// patch sums along rows (step 1) and then along columns (step = row length), each over a whole
// block at once (entries that straddle two rows are computed and never read). Sixteen sums at a
// time are kept in registers.
ANAMORPH_KERNEL_BODY void box_sums_body(int n, int taps, int step, const float* __restrict in,
                                        float* __restrict out) {
  int i = 0;
  for (; i + kLanes <= n; i += kLanes) {
    Lanes sum, v;
    load(sum, in + i);
    for (int t = 1; t < taps; ++t) {
      load(v, in + i + t * step);
      sum += v;
    }
    store(out + i, sum);
  }
  for (; i < n; ++i) {
    float sum = in[i];
    for (int t = 1; t < taps; ++t) sum += in[i + t * step];
    out[i] = sum;
  }
}
constexpr simd::Kernel<box_sums_body> box_sums;

// exp(-max(distance / k², 0)) · coverage, and 0 beyond kFar.
ANAMORPH_KERNEL_BODY void weights_kernel_body(
    int n, const float* distance, float inv_k2, const float* __restrict coverage,
    float* out) {  // (distance and out may be the same array)
  for (int i = 0; i < n; ++i) {
    const float d = std::max(distance[i] * inv_k2, 0.0f);
    const float e = exp_neg(std::min(d, kFar)) * coverage[i];
    out[i] = d < kFar ? e : 0.0f;
  }
}
constexpr simd::Kernel<weights_kernel_body> weights_kernel;

ANAMORPH_KERNEL_BODY void accumulate_body(int n, const float* __restrict w,
                                          const float* __restrict v, float* __restrict acc) {
  for (int i = 0; i < n; ++i) acc[i] += w[i] * v[i];
}
constexpr simd::Kernel<accumulate_body> accumulate;

// Per-pixel distances d(p, p + (dx, dy)) (channel means; 0 for absent pairs) and pair counts
// over r grown by the patch radius, row-major with row length r.width() + 2f. Returns whether
// every pair there is present (inside the image and covered).
bool pixel_distances(const Guide& g, int f, const Rect& r, int dx, int dy, float* dist,
                     float* count) {
  const Planes& val = *g.value;
  const int w = val.width(), h = val.height();
  const int pw = r.width() + 2 * f, ph = r.height() + 2 * f, px0 = r.x0 - f, py0 = r.y0 - f;
  const float* cov = g.coverage->plane(0);
  size_t present = 0;
  for (int yy = 0; yy < ph; ++yy) {
    float* drow = dist + size_t(yy) * pw;
    float* crow = count + size_t(yy) * pw;
    std::fill_n(drow, pw, 0.0f);
    std::fill_n(crow, pw, 0.0f);
    const int y = py0 + yy, yq = y + dy;
    if (y < 0 || y >= h || yq < 0 || yq >= h) continue;
    const int xa = std::max({px0, 0, -dx}), xb = std::min({px0 + pw, w, w - dx});
    if (xa >= xb) continue;
    const size_t p = size_t(y) * w + xa, q = size_t(yq) * w + xa + dx;
    RowPair rows;
    for (int c = 0; c < val.channels(); ++c) {
      rows.gp[c] = val.plane(c) + p;
      rows.gq[c] = val.plane(c) + q;
      rows.vp[c] = g.variance->plane(c) + p;
      rows.vq[c] = g.variance->plane(c) + q;
    }
    present += (val.channels() == 3 ? pair_distances3.get() : pair_distances1.get())(
        xb - xa, rows, cov + p, cov + q, drow + (xa - px0), crow + (xa - px0));
  }
  return present == size_t(pw) * size_t(ph);
}

}  // namespace

PatchScratch::PatchScratch(int side, int patch_radius, MemoryMeter* meter)
    : dist_(size_t(side + 2 * patch_radius) * (side + 2 * patch_radius), meter),
      count_(dist_.size(), meter),
      row_dist_(dist_.size(), meter),
      row_count_(dist_.size(), meter) {}

size_t PatchScratch::bytes(int side, int patch_radius) {
  const size_t padded = size_t(side + 2 * patch_radius);
  return sizeof(float) * 4 * padded * padded;
}

void patch_distances(const Guide& g, int patch_radius, const Rect& r, int dx, int dy,
                     PatchScratch& scratch, float* out) {
  const int f = patch_radius, rw = r.width(), rh = r.height(), pw = rw + 2 * f, taps = 2 * f + 1;
  const int ph = rh + 2 * f;
  const bool all = pixel_distances(g, f, r, dx, dy, scratch.dist(), scratch.count());
  // Patch sums: along rows into row_*, then along columns back into dist and count.
  const int along_rows = ph * pw - 2 * f, along_cols = rh * pw;
  box_sums(along_rows, taps, 1, scratch.dist(), scratch.row_dist());
  box_sums(along_cols, taps, pw, scratch.row_dist(), scratch.dist());
  if (!all) {
    box_sums(along_rows, taps, 1, scratch.count(), scratch.row_count());
    box_sums(along_cols, taps, pw, scratch.row_count(), scratch.count());
  }
  for (int y = 0; y < rh; ++y) {
    const float* sum = scratch.dist() + size_t(y) * pw;
    const float* count = scratch.count() + size_t(y) * pw;
    float* o = out + size_t(y) * rw;
    if (all) {
      const float inv = 1.0f / float(taps * taps);
      for (int x = 0; x < rw; ++x) o[x] = sum[x] * inv;
    } else {
      for (int x = 0; x < rw; ++x) o[x] = sum[x] / std::max(count[x], 1.0f);
    }
  }
}

void weights_from_distances(int n, const float* distance, float k, const float* coverage,
                            float* out) {
  weights_kernel(n, distance, 1.0f / (k * k), coverage, out);
}

namespace {

struct FilterScratch {
  FilterScratch(int channels, int patch_radius, MemoryMeter* meter)
      : patch(kFilterTile, patch_radius, meter),
        weight(size_t(kFilterTile) * kFilterTile, meter),
        wsum(size_t(kFilterTile) * kFilterTile, meter),
        acc(size_t(kFilterTile) * kFilterTile * channels, meter) {}
  PatchScratch patch;
  MeteredFloats weight, wsum, acc;
};

// The NL-means sums of one tile, in a fixed order: offsets row by row, then inputs, channels.
void filter_tile(const Guide& g, const PatchKernel& kernel, int radius, const Rect& r,
                 std::span<const Planes* const> in, std::span<Planes* const> out,
                 FilterScratch& s) {
  const int w = g.value->width(), h = g.value->height(), rw = r.width();
  const size_t n = r.area();
  std::fill_n(s.wsum.data(), n, 0.0f);
  std::fill_n(s.acc.data(), s.acc.size(), 0.0f);
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx) {
      const int xa = std::max(r.x0, -dx), xb = std::min(r.x1, w - dx);
      if (xa >= xb) continue;
      patch_distances(g, kernel.patch_radius, r, dx, dy, s.patch, s.weight.data());
      for (int y = std::max(r.y0, -dy); y < std::min(r.y1, h - dy); ++y) {
        const size_t t = size_t(y - r.y0) * rw + (xa - r.x0), q = size_t(y + dy) * w + xa + dx;
        float* wt = s.weight.data() + t;
        weights_from_distances(xb - xa, wt, kernel.k, g.coverage->plane(0) + q, wt);
        for (int i = 0; i < xb - xa; ++i) s.wsum[t + i] += wt[i];
        size_t channel = 0;
        for (const Planes* p : in)
          for (int c = 0; c < p->channels(); ++c, ++channel)
            accumulate(xb - xa, wt, p->plane(c) + q, s.acc.data() + channel * n + t);
      }
    }
  size_t channel = 0;
  for (Planes* p : out)
    for (int c = 0; c < p->channels(); ++c, ++channel)
      for (int y = r.y0; y < r.y1; ++y)
        for (int x = r.x0; x < r.x1; ++x) {
          const size_t t = size_t(y - r.y0) * rw + (x - r.x0);
          const bool covered = g.coverage->at(0, x, y) > 0.0f;
          p->at(c, x, y) = covered ? s.acc[channel * n + t] / s.wsum[t] : 0.0f;
        }
}

}  // namespace

void check_guide(const Guide& g) {
  const int c = g.value->channels();
  if ((c != 1 && c != 3) || g.variance->channels() != c || g.coverage->channels() != 1 ||
      g.variance->pixels() != g.value->pixels() || g.coverage->pixels() != g.value->pixels())
    throw std::invalid_argument("nfor: a guide has 1 or 3 channels, with matching planes");
}

namespace {

// Whether the guide's variance is 0 everywhere within `reach` of r.
bool noise_free(const Guide& g, const Rect& r, int reach) {
  const Planes& v = *g.variance;
  const int x0 = std::max(0, r.x0 - reach), x1 = std::min(v.width(), r.x1 + reach);
  const int y0 = std::max(0, r.y0 - reach), y1 = std::min(v.height(), r.y1 + reach);
  for (int c = 0; c < v.channels(); ++c)
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x)
        if (v.at(c, x, y) != 0.0f) return false;
  return true;
}

void copy_tile(const Rect& r, std::span<const Planes* const> in, std::span<Planes* const> out) {
  for (size_t i = 0; i < in.size(); ++i)
    for (int c = 0; c < in[i]->channels(); ++c)
      for (int y = r.y0; y < r.y1; ++y)
        for (int x = r.x0; x < r.x1; ++x) out[i]->at(c, x, y) = in[i]->at(c, x, y);
}

}  // namespace

void nl_means(const Guide& g, const PatchKernel& kernel, int window_radius,
              std::span<const Planes* const> in, std::span<Planes* const> out, MemoryMeter* meter,
              bool copy_noise_free) {
  check_guide(g);
  int channels = 0;
  for (const Planes* p : in) channels += p->channels();
  const TileLayout tiles(g.value->width(), g.value->height(), kFilterTile);
  const int reach = window_radius + kernel.patch_radius;
  parallel_chunks(0, tiles.count(), 1, [&](size_t lo, size_t hi) {
    FilterScratch scratch(channels, kernel.patch_radius, meter);
    for (size_t t = lo; t < hi; ++t) {
      const Rect r = tiles.rect(t);
      if (copy_noise_free && noise_free(g, r, reach))
        copy_tile(r, in, out);
      else
        filter_tile(g, kernel, window_radius, r, in, out, scratch);
    }
  });
}

size_t nl_means_scratch_bytes(int /*window_radius*/, int patch_radius, int channels) {
  const size_t tile = size_t(kFilterTile) * kFilterTile;
  return PatchScratch::bytes(kFilterTile, patch_radius) + sizeof(float) * tile * (2 + channels);
}

}  // namespace anamorph::nfor
