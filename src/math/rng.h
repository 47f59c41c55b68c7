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
  // Uniform in [0, 1).
  double uniform() { return double(next_u32()) * 0x1p-32; }

  static Rng for_sample(uint32_t px, uint32_t py, uint32_t sample, uint64_t seed) {
    const uint64_t pixel = (uint64_t(py) << 32) | px;
    return Rng(mix64(pixel ^ mix64(seed)), mix64((uint64_t(sample) << 1) ^ mix64(seed + pixel)));
  }

 private:
  uint64_t state_ = 0x853c49e6748fea9bULL, inc_ = 0xda3e39cb94b95bdbULL;
};

}  // namespace anamorph
