// Pixel sample positions. `center`: exactly the pixel center. `stratified`: Latin hypercube
// (N-rooks) over the pixel's spp samples, jittered, so any spp is well stratified. `random`:
// independent uniform. The Gaussian filter warps the position by filter importance sampling,
// so every sample has weight 1 and no sample crosses into another pixel's sums.
#pragma once

#include <cmath>
#include <string>

#include "math/rng.h"
#include "math/vec.h"

namespace anamorph {

enum class SamplerKind { Center, Stratified, Random };

inline SamplerKind sampler_kind(const std::string& s) {
  return s == "center" ? SamplerKind::Center
                       : (s == "random" ? SamplerKind::Random : SamplerKind::Stratified);
}

// Kensler's hash-based permutation of [0, n) (Correlated Multi-Jittered Sampling, 2013).
inline uint32_t permute(uint32_t i, uint32_t n, uint32_t key) {
  uint32_t w = n - 1;
  w |= w >> 1, w |= w >> 2, w |= w >> 4, w |= w >> 8, w |= w >> 16;
  do {
    i ^= key;
    i *= 0xe170893d;
    i ^= key >> 16;
    i ^= (i & w) >> 4;
    i ^= key >> 8;
    i *= 0x0929eb3f;
    i ^= key >> 23;
    i ^= (i & w) >> 1;
    i *= 1 | key >> 27;
    i *= 0x6935fa69;
    i ^= (i & w) >> 11;
    i *= 0x74dcb303;
    i ^= (i & w) >> 2;
    i *= 0x9e501cc3;
    i ^= (i & w) >> 2;
    i *= 0xc860a3df;
    i &= w;
    i ^= i >> 5;
  } while (i >= n);
  return (i + key) % n;
}

// Offset of sample `s` of `n` inside the pixel, in [0,1)^2 (before filter warping).
inline Vec2 pixel_offset(SamplerKind k, uint32_t s, uint32_t n, uint32_t pixel_key, Rng& rng) {
  switch (k) {
    case SamplerKind::Center:
      return {0.5, 0.5};
    case SamplerKind::Random: {
      const double a = rng.uniform();
      return {a, rng.uniform()};
    }
    case SamplerKind::Stratified:
    default: {
      const double jx = rng.uniform(), jy = rng.uniform();
      const uint32_t sx = permute(s, n, pixel_key * 0x68bc21ebu + 1);
      const uint32_t sy = permute(s, n, pixel_key * 0x02e5be93u + 7);
      return {(sx + jx) / n, (sy + jy) / n};
    }
  }
}

// Truncated radial Gaussian (sigma = radius / 3) by inverse CDF: offset from the pixel center.
inline Vec2 gaussian_offset(Vec2 u, double radius) {
  const double sigma = radius / 3;
  const double tail = 1 - std::exp(-radius * radius / (2 * sigma * sigma));
  const double r = sigma * std::sqrt(-2 * std::log(1 - u.x * tail));
  const double phi = 2 * kPi * u.y;
  return {r * std::cos(phi), r * std::sin(phi)};
}

}  // namespace anamorph
