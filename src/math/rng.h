// Deterministic random numbers. Every pixel sample gets its own PCG32 stream seeded by hashing
// (pixel, sample index, scene seed), so an image does not depend on thread scheduling.
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
// 2020): the first two Sobol' dimensions form a (0,2)-sequence, so every power-of-two prefix of a
// pixel's samples is stratified in every elementary interval; nested uniform scrambling (hashed
// per pixel and dimension pair) randomises it without losing that, and scrambling the index
// decorrelates the pairs from each other.
namespace qmc {
inline uint32_t reverse_bits(uint32_t x) {
  x = (x << 16) | (x >> 16);
  x = ((x & 0x00ff00ffu) << 8) | ((x & 0xff00ff00u) >> 8);
  x = ((x & 0x0f0f0f0fu) << 4) | ((x & 0xf0f0f0f0u) >> 4);
  x = ((x & 0x33333333u) << 2) | ((x & 0xccccccccu) >> 2);
  x = ((x & 0x55555555u) << 1) | ((x & 0xaaaaaaaau) >> 1);
  return x;
}
// Laine and Karras' hash: each bit is flipped depending only on itself and lower bits.
inline uint32_t lk_permute(uint32_t x, uint32_t seed) {
  x += seed;
  x ^= x * 0x6c50b47cu;
  x ^= x * 0xb82f1e52u;
  x ^= x * 0xc7afe638u;
  x ^= x * 0x8d22f6e6u;
  return x;
}
// Nested uniform (Owen) scrambling of a 32-bit binary fraction.
inline uint32_t owen(uint32_t x, uint32_t seed) {
  return reverse_bits(lk_permute(reverse_bits(x), seed));
}
// Sobol' dimension 1 (dimension 0 is the bit-reversed index).
inline uint32_t sobol1(uint32_t i) {
  uint32_t r = 0;
  for (uint32_t v = 1u << 31; i; i >>= 1, v ^= v >> 1)
    if (i & 1) r ^= v;
  return r;
}
inline uint32_t hash32(uint64_t k) { return uint32_t(mix64(k) >> 32); }
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
  // Uniform in [0, 1). The first qmc_dims numbers of a stream with qmc() set come from the
  // pixel's scrambled Sobol' points, the rest from PCG32.
  double uniform() {
    if (dim_ < qmc_dims_) {
      const double v = qmc_value(dim_ >> 1, dim_ & 1);
      ++dim_;
      return v;
    }
    return double(next_u32()) * 0x1p-32;
  }
  // Two numbers meant as one 2D sample: a fresh Sobol' pair while the QMC dimensions last (so the
  // pair is stratified in 2D across the pixel's samples).
  void uniform2(double& a, double& b) {
    if ((dim_ & 1) && dim_ < qmc_dims_) ++dim_;
    a = uniform();
    b = uniform();
  }
  // Makes the first `dims` numbers (at most 32) sample `index` of a progressive low-discrepancy
  // sequence scrambled by `key` (one per pixel): consecutive sample indices of one pixel are then
  // stratified against each other, dimension pair by dimension pair.
  void qmc(uint32_t index, uint64_t key, int dims) {
    qmc_index_ = index;
    qmc_key_ = key;
    qmc_dims_ = uint8_t(dims);
    dim_ = 0;
  }
  bool qmc_active() const { return dim_ < qmc_dims_; }

  static Rng for_sample(uint32_t px, uint32_t py, uint32_t sample, uint64_t seed) {
    const uint64_t pixel = (uint64_t(py) << 32) | px;
    return Rng(mix64(pixel ^ mix64(seed)), mix64((uint64_t(sample) << 1) ^ mix64(seed + pixel)));
  }

 private:
  double qmc_value(uint32_t pair, int component) const {
    const uint32_t seed = qmc::hash32(qmc_key_ ^ (uint64_t(pair) * 0x9E3779B97F4A7C15ULL));
    const uint32_t i = qmc::owen(qmc_index_, seed);
    const uint32_t x = component == 0 ? qmc::reverse_bits(i) : qmc::sobol1(i);
    return double(qmc::owen(x, qmc::hash32(uint64_t(seed) << 1 | uint32_t(component)))) * 0x1p-32;
  }
  uint64_t state_ = 0x853c49e6748fea9bULL, inc_ = 0xda3e39cb94b95bdbULL;
  uint64_t qmc_key_ = 0;
  uint32_t qmc_index_ = 0;
  uint8_t qmc_dims_ = 0, dim_ = 0;
};

}  // namespace anamorph
