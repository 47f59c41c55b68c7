// The denoiser (src/denoise) on a 512 × 512 frame: two noisy half buffers of a piecewise-smooth
// image with albedo, normal and depth features, and a fisheye-like disc of coverage (the corners
// have no ray), as a render would hand it over.
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "denoise/denoise.h"
#include "math/rng.h"

namespace anamorph {
namespace {

struct Frame {
  explicit Frame(int n)
      : side(n),
        a(size_t(n) * n * 3),
        b(a.size()),
        albedo(a.size()),
        normal(a.size()),
        depth(size_t(n) * n),
        coverage(size_t(n) * n) {
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const size_t i = size_t(y) * n + x;
        const double u = (x + 0.5) / n - 0.5, v = (y + 0.5) / n - 0.5, r = std::hypot(u, v);
        coverage[i] = float(std::clamp((0.5 - r) * n + 0.5, 0.0, 1.0));
        const bool stripe = (x / 24 + y / 40) % 2 == 0;
        const float nz = float(std::sqrt(std::max(0.0, 1 - 4 * r * r)));
        const float n3[3] = {float(2 * u), float(2 * v), nz};
        for (int c = 0; c < 3; ++c) {
          albedo[3 * i + c] = stripe ? 0.8f - 0.2f * c : 0.2f + 0.25f * c;
          normal[3 * i + c] = n3[c];
          const float clean = albedo[3 * i + c] * (0.2f + 0.8f * nz);
          a[3 * i + c] = clean * float(1 + 0.5 * noise(2 * (3 * i + c)));
          b[3 * i + c] = clean * float(1 + 0.5 * noise(2 * (3 * i + c) + 1));
        }
        depth[i] = float(2 - nz);
      }
  }
  static double noise(uint64_t k) { return double(mix64(k) >> 11) * 0x1.0p-53 * 2 - 1; }
  DenoiseInput input() const {
    DenoiseInput in;
    in.width = in.height = side;
    in.color_a = a.data();
    in.color_b = b.data();
    in.coverage = coverage.data();
    in.features = {{albedo.data(), albedo.data(), 3},
                   {normal.data(), normal.data(), 3},
                   {depth.data(), depth.data(), 1}};
    return in;
  }
  int side;
  std::vector<float> a, b, albedo, normal, depth, coverage;
};

void BM_Denoise(benchmark::State& state) {
  const Frame frame(int(state.range(0)));
  std::vector<float> out(frame.a.size());
  DenoiseOptions o;
  o.second_pass = state.range(1) != 0;
  for (auto _ : state) {
    denoise(frame.input(), o, out.data());
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(state.iterations() * int64_t(frame.side) * frame.side);
}
BENCHMARK(BM_Denoise)->Args({512, 1})->Args({512, 0})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace anamorph
