// The stratified sampler's sequence (Rng::qmc): every dimension a path draws, however deep, comes
// from a pixel's padded Owen-scrambled Sobol' points.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "math/rng.h"
#include "math/vec.h"

namespace anamorph {

namespace {

constexpr int kBounces = 40;  // path-like draws: 1 + 40 * 3 pairs, then a lone number per bounce

// Sample `s` of pixel `key` drawn the way the path tracer draws: a 2D pixel position, then per
// bounce two 2D samples, a pair of lone numbers (light pick, lobe) and a Russian-roulette number.
struct Draws {
  double pair[1 + 2 * kBounces][2];
  double lone[kBounces][3];
};
Draws draw(uint64_t key, uint32_t s) {
  Rng r = Rng::for_sample(7, 9, s, 42);
  r.qmc(s, key);
  Draws d;
  r.uniform2(d.pair[0][0], d.pair[0][1]);
  for (int b = 0; b < kBounces; ++b) {
    r.uniform2(d.pair[1 + 2 * b][0], d.pair[1 + 2 * b][1]);
    r.uniform2(d.pair[2 + 2 * b][0], d.pair[2 + 2 * b][1]);
    for (double& u : d.lone[b]) u = r.uniform();
  }
  return d;
}

// How many of the (2^m) elementary intervals of area 2^-m of one shape do not hold exactly one of
// the first 2^m points (x, y).
int badly_filled(const std::vector<Draws>& d, int pair, int m, int kx) {
  const int cx = 1 << kx, cy = 1 << (m - kx);
  std::vector<int> count(size_t(1) << m, 0);
  for (int s = 0; s < (1 << m); ++s)
    count[size_t(int(d[size_t(s)].pair[pair][1] * cy) * cx +
                 int(d[size_t(s)].pair[pair][0] * cx))]++;
  int bad = 0;
  for (int c : count) bad += c != 1;
  return bad;
}

}  // namespace

TEST(Qmc, EveryPowerOfTwoPrefixIsStratifiedInEveryPairAtAnyDepth) {
  // For pixel keys and dimension pairs from the first to the 81st (bounce 40): the first 2^m
  // samples (m = 0..8) put exactly one point in every elementary interval of area 2^-m (every
  // shape 2^kx x 2^(m-kx)), and the lone numbers (the first of each bounce's trio, and the
  // roulette number) one point in every interval of length 2^-m.
  for (uint64_t key : {uint64_t(0x1234567), mix64(99)}) {
    std::vector<Draws> d;
    for (uint32_t s = 0; s < 256; ++s) d.push_back(draw(key, s));
    for (int pair : {0, 1, 2, 9, 40, 80})
      for (int m = 0; m <= 8; ++m)
        for (int kx = 0; kx <= m; ++kx)
          ASSERT_EQ(badly_filled(d, pair, m, kx), 0)
              << "key " << key << ", pair " << pair << ", " << (1 << m) << " samples, " << (1 << kx)
              << "x" << (1 << (m - kx)) << " cells";
    for (int b : {0, 3, 39})
      for (int j : {0, 2})
        for (int m = 0; m <= 8; ++m) {
          std::vector<int> count(size_t(1) << m, 0);
          for (int s = 0; s < (1 << m); ++s) count[size_t(d[size_t(s)].lone[b][j] * (1 << m))]++;
          for (size_t c = 0; c < count.size(); ++c)
            ASSERT_EQ(count[c], 1) << "key " << key << ", bounce " << b << " number " << j << ", "
                                   << (1 << m) << " samples, interval " << c;
        }
  }
}

TEST(Qmc, DeepPairsIntegrateBetterThanIndependentNumbersAndAreUncorrelated) {
  // 1024 pixels of 64 samples integrate a disk's indicator (the kind of edge a renderer meets;
  // exact value pi/4) in the pair of bounce 30's BSDF sample. Stratified points: error ~ n^-3/4
  // against n^-1/2 for independent ones (about 0.35 of it at n = 64). Across pairs the padding
  // must leave no correlation: the mean of x(pair 1) * x(pair 61) is 1/4.
  constexpr int kPixels = 1024, kSpp = 64, kPair = 2 + 2 * 30;
  double se_qmc = 0, se_rnd = 0, cross = 0;
  for (int p = 0; p < kPixels; ++p) {
    double sum_q = 0, sum_r = 0;
    for (uint32_t s = 0; s < kSpp; ++s) {
      const Draws d = draw(mix64(uint64_t(p) + 1), s);
      const double* q = d.pair[kPair];
      sum_q += q[0] * q[0] + q[1] * q[1] < 1;
      cross += d.pair[1][0] * d.pair[kPair - 1][0];
      Rng r = Rng::for_sample(uint32_t(p), 0, s, 42);
      const double a = r.uniform(), b = r.uniform();
      sum_r += a * a + b * b < 1;
    }
    se_qmc += std::pow(sum_q / kSpp - kPi / 4, 2);
    se_rnd += std::pow(sum_r / kSpp - kPi / 4, 2);
  }
  const double rmse_qmc = std::sqrt(se_qmc / kPixels), rmse_rnd = std::sqrt(se_rnd / kPixels);
  EXPECT_LT(rmse_qmc, 0.5 * rmse_rnd)
      << "RMSE stratified " << rmse_qmc << ", independent " << rmse_rnd;
  // Independent products: sd sqrt(7/144) / sqrt(65536) = 0.00086; 0.004 is over 4.5 of them.
  EXPECT_NEAR(cross / (kPixels * kSpp), 0.25, 0.004);
}

TEST(Qmc, SameSampleSameNumbersAndPairsDiffer) {
  const Draws a = draw(0x1234567, 5), b = draw(0x1234567, 5), c = draw(0x1234568, 5);
  int same_key = 0, other_key = 0, pairs_alike = 0;
  for (int i = 0; i < 1 + 2 * kBounces; ++i) {
    same_key += a.pair[i][0] == b.pair[i][0] && a.pair[i][1] == b.pair[i][1];
    other_key += a.pair[i][0] == c.pair[i][0];
    if (i > 0) pairs_alike += a.pair[i][0] == a.pair[i - 1][0];
  }
  EXPECT_EQ(same_key, 1 + 2 * kBounces);
  EXPECT_LT(other_key, 2) << "another pixel's key repeats the numbers";
  EXPECT_LT(pairs_alike, 2) << "neighbouring dimension pairs repeat each other";
}

}  // namespace anamorph
