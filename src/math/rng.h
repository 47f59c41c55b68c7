// Deterministic random numbers. Every pixel sample gets its own stream seeded by hashing (pixel,
// sample index, scene seed), so an image does not depend on thread scheduling: PCG32, or the
// pixel's scrambled Sobol' points (Rng::qmc).
#pragma once

#include <cstdint>

namespace anamorph {

// 64-bit finalizer from MurmurHash3; good avalanche for seed mixing.
inline uint64_t mix64(uint64_t k) {
  k ^= k >> 33;
  k *= 0xff51afd7ed558ccdULL;
  k ^= k >> 33;
  k *= 0xc4ceb9fe1a85ec53ULL;
  k ^= k >> 33;
  return k;
}

// Owen-scrambled, shuffled Sobol' points (Burley, "Practical Hash-based Owen Scrambling", JCGT
// 2020), padded: every dimension pair of a path is drawn from the first two Sobol' dimensions, a
// (0,2)-sequence, so every power-of-two prefix of a pixel's samples is stratified in every
// elementary interval of every pair; nested uniform scrambling (hashed per pixel and dimension
// pair) randomises each pair without losing that, and scrambling the index per pair decorrelates
// the pairs from each other (as pbrt-v4's PaddedSobolSampler pads, but with a nested shuffle of
// the index, which keeps power-of-two prefixes whole where a permutation over spp would not).
namespace qmc {
inline uint32_t reverse_bits(uint32_t x) {
  x = __builtin_bswap32(x);  // bytes reversed: one instruction for the first two of five swaps
  x = ((x & 0x0f0f0f0fu) << 4) | ((x & 0xf0f0f0f0u) >> 4);
  x = ((x & 0x33333333u) << 2) | ((x & 0xccccccccu) >> 2);
  x = ((x & 0x55555555u) << 1) | ((x & 0xaaaaaaaau) >> 1);
  return x;
}
// Nested uniform (Owen) scrambling of a bit-reversed value by Laine and Karras' hash: each bit is
// flipped depending only on itself and the bits below it (the higher digits of the unreversed
// value). Vegdahl's better-mixing variant ("Building a Better LK Hash", 2021) was measured in its
// place: the bench/cycles box scenes 2-5 % noisier, Cornell 1-2 % less (docs/performance.md).
inline uint32_t lk_permute(uint32_t x, uint32_t seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}
// Sobol' dimension 1 with its bits reversed (dimension 0 is the bit-reversed index): each set
// bit j of i adds row j of Pascal's triangle mod 2. Linear over GF(2), so four byte tables.
struct Sobol1Tables {
  uint32_t t[4][256];
  constexpr Sobol1Tables() : t{} {
    uint32_t rows[32] = {};
    uint32_t w = 1;
    for (int j = 0; j < 32; ++j, w ^= w << 1) rows[j] = w;
    for (int k = 0; k < 4; ++k)
      for (uint32_t b = 0; b < 256; ++b) {
        uint32_t r = 0;
        for (int j = 0; j < 8; ++j)
          if (b >> j & 1) r ^= rows[8 * k + j];
        t[k][b] = r;
      }
  }
};
inline constexpr Sobol1Tables kSobol1{};
inline uint32_t sobol1_reversed(uint32_t i) {
  return kSobol1.t[0][i & 255] ^ kSobol1.t[1][(i >> 8) & 255] ^ kSobol1.t[2][(i >> 16) & 255] ^
         kSobol1.t[3][i >> 24];
}
}  // namespace qmc

class Rng {
 public:
  Rng() = default;
  Rng(uint64_t seq, uint64_t seed) { set_sequence(seq, seed); }
  void set_sequence(uint64_t seq, uint64_t seed) {
    state_ = 0u;
    inc_ = (seq << 1u) | 1u;
    next_u32();
    state_ += seed;
    next_u32();
  }
  uint32_t next_u32() {
    const uint64_t old = state_;
    state_ = old * 6364136223846793005ULL + inc_;
    const auto xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
    const auto rot = uint32_t(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31));
  }
  // Uniform in [0, 1). A stream with qmc() set draws every number from the pixel's scrambled
  // Sobol' points (two dimensions per point); otherwise from PCG32.
  double uniform() {
    if (qmc_on_) {
      if (dim_++ & 1) return double(pending_) * 0x1p-32;
      uint32_t x;
      qmc_pair(dim_ >> 1, x, pending_);
      return double(x) * 0x1p-32;
    }
    return double(next_u32()) * 0x1p-32;
  }
  // Two numbers meant as one 2D sample: with a QMC stream a fresh Sobol' pair (so the pair is
  // stratified in 2D across the pixel's samples; a lone number left over is skipped).
  void uniform2(double& a, double& b) {
    if (qmc_on_ && (dim_ & 1)) ++dim_;
    a = uniform();
    b = uniform();
  }
  // Makes every later number of this stream come from sample `index` of a progressive
  // low-discrepancy sequence scrambled by `key` (one per pixel): consecutive sample indices of one
  // pixel are then stratified against each other, dimension pair by dimension pair, in every
  // dimension a path draws.
  void qmc(uint32_t index, uint64_t key) {
    qmc_rindex_ = qmc::reverse_bits(index);
    qmc_key_ = key;
    qmc_on_ = true;
    dim_ = 0;
  }
  bool qmc_active() const { return qmc_on_; }

  static Rng for_sample(uint32_t px, uint32_t py, uint32_t sample, uint64_t seed) {
    const uint64_t pixel = (uint64_t(py) << 32) | px;
    return Rng(mix64(pixel ^ mix64(seed)), mix64((uint64_t(sample) << 1) ^ mix64(seed + pixel)));
  }

 private:
  // Point `index` of dimension pair `pair`: the index shuffled by nested uniform scrambling, its
  // Sobol' coordinates, each scrambled likewise. Owen scrambling works on bit-reversed values,
  // which the reversed index and the reversed dimension 1 give for free.
  void qmc_pair(uint32_t pair, uint32_t& x, uint32_t& y) const {
    const uint64_t h = mix64(qmc_key_ ^ (uint64_t(pair) * 0x9E3779B97F4A7C15ULL));
    const uint32_t shuffled_r = qmc::lk_permute(qmc_rindex_, uint32_t(h));  // reversed
    const uint32_t shuffled = qmc::reverse_bits(shuffled_r);
    // Dimension 0 is reverse_bits(shuffled); Owen-scrambling it = reverse(lk(shuffled)).
    x = qmc::reverse_bits(qmc::lk_permute(shuffled, uint32_t(h >> 32)));
    y = qmc::reverse_bits(
        qmc::lk_permute(qmc::sobol1_reversed(shuffled), uint32_t(h >> 32) * 0x2545F491u + 1));
  }
  uint64_t state_ = 0x853c49e6748fea9bULL, inc_ = 0xda3e39cb94b95bdbULL;
  uint64_t qmc_key_ = 0;
  uint32_t qmc_rindex_ = 0, pending_ = 0;  // the sample index, bit-reversed; a pair's y
  uint32_t dim_ = 0;                       // numbers drawn since qmc()
  bool qmc_on_ = false;
};

}  // namespace anamorph
