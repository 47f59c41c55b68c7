// Synthetic half buffers with a known clean image, for the denoiser's tests: feature planes
// (albedo, normal, depth) that the test draws, a clean colour made from them, coverage for a
// no-ray region and a partially covered rim, and Gaussian noise of known variance in each half.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "denoise/denoise.h"
#include "math/rng.h"

namespace anamorph::test {

// A standard normal number from a hash of (seed, index) (Box-Muller): the same on every
// platform and independent of evaluation order.
inline double gaussian(uint64_t seed, uint64_t index) {
  const uint64_t h1 = mix64(seed * 0x9e3779b97f4a7c15ULL + 2 * index + 1);
  const uint64_t h2 = mix64(h1 ^ (2 * index + 2));
  const double u1 = (double(h1 >> 11) + 1.0) * 0x1.0p-53, u2 = double(h2 >> 11) * 0x1.0p-53;
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * 3.14159265358979323846 * u2);
}

struct Synthetic {
  int width = 0, height = 0;
  std::vector<float> albedo, normal, depth;  // 3, 3, 1 channels; the same in both halves
  std::vector<float> coverage;               // 1 channel
  std::vector<float> clean;                  // straight RGB
  std::vector<float> a, b;                   // the noisy halves

  Synthetic(int w, int h)
      : width(w),
        height(h),
        albedo(size_t(w) * h * 3, 0.5f),
        normal(size_t(w) * h * 3, 0.0f),
        depth(size_t(w) * h, 1.0f),
        coverage(size_t(w) * h, 1.0f),
        clean(size_t(w) * h * 3) {
    for (size_t i = 0; i < pixels(); ++i) normal[3 * i + 2] = 1.0f;
  }
  size_t pixels() const { return size_t(width) * size_t(height); }

  // clean = shade(pixel index) for every pixel.
  void shade(const std::function<void(size_t, float*)>& f) {
    for (size_t i = 0; i < pixels(); ++i) f(i, &clean[3 * i]);
  }
  // Noise of standard deviation sigma per half and channel, divided by sqrt(coverage) (a
  // partially covered pixel's straight colour averages fewer samples).
  void add_noise(float sigma, uint64_t seed) {
    a.assign(clean.size(), 0.0f);
    b.assign(clean.size(), 0.0f);
    for (size_t i = 0; i < clean.size(); ++i) {
      const float cov = coverage[i / 3];
      const float s = cov > 0 ? sigma / std::sqrt(cov) : 0.0f;
      a[i] = clean[i] + s * float(gaussian(seed, 2 * i));
      b[i] = clean[i] + s * float(gaussian(seed, 2 * i + 1));
    }
  }
  DenoiseInput input() const {
    DenoiseInput in;
    in.width = width;
    in.height = height;
    in.color_a = a.data();
    in.color_b = b.data();
    in.coverage = coverage.data();
    in.features = {{albedo.data(), albedo.data(), 3},
                   {normal.data(), normal.data(), 3},
                   {depth.data(), depth.data(), 1}};
    return in;
  }
  // Coverage of a disc (centre cx, cy, radius r in pixels): the fraction of 16×16 points per
  // pixel inside it; outside the disc, coverage 0.
  void cover_disc(double cx, double cy, double r) {
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        int in = 0;
        for (int j = 0; j < 16; ++j)
          for (int i = 0; i < 16; ++i) {
            const double px = x + (i + 0.5) / 16 - cx, py = y + (j + 0.5) / 16 - cy;
            in += px * px + py * py <= r * r;
          }
        coverage[size_t(y) * width + x] = float(in) / 256.0f;
      }
  }
};

// Mean squared error over the covered pixels (3 channels) of `image` against the clean image,
// over the pixels where keep(x, y) holds.
inline double mse(const Synthetic& s, const std::vector<float>& image,
                  const std::function<bool(int, int)>& keep = nullptr) {
  double sum = 0;
  size_t n = 0;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      const size_t i = size_t(y) * s.width + x;
      if (!(s.coverage[i] > 0) || (keep && !keep(x, y))) continue;
      for (int c = 0; c < 3; ++c) {
        const double d = double(image[3 * i + c]) - s.clean[3 * i + c];
        sum += d * d;
        ++n;
      }
    }
  return n ? sum / double(n) : 0.0;
}

// The mean of the two halves: the undenoised image at the full sample count.
inline std::vector<float> mean_of_halves(const Synthetic& s) {
  std::vector<float> m(s.a.size());
  for (size_t i = 0; i < m.size(); ++i) m[i] = 0.5f * (s.a[i] + s.b[i]);
  return m;
}

}  // namespace anamorph::test
