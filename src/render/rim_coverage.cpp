#include "render/rim_coverage.h"

#include <algorithm>

#include "math/parallel.h"
#include "render/sampler.h"

namespace anamorph {

bool rim_coverage_applies(const Camera& cam, const RenderSettings& rs) {
  return rs.sampler != SamplerKind::Center && !cam.uses_lens_or_time();
}

namespace {

// The covered fraction of pixel (x, y): g × g cell-centred positions, in batches.
float pixel_coverage(const Camera& cam, const RenderSettings& rs, int width, int height, int x,
                     int y, int g) {
  const bool gaussian = rs.filter == PixelFilter::Gaussian;
  CameraSample s[kCameraBatch];
  CameraRayBatch rays;
  const int n = g * g;
  int covered = 0;
  for (int k0 = 0; k0 < n; k0 += kCameraBatch) {
    const int m = std::min(kCameraBatch, n - k0);
    for (int j = 0; j < m; ++j) {
      const int k = k0 + j;
      Vec2 off{(k % g + 0.5) / g, (k / g + 0.5) / g};
      if (gaussian) off = gaussian_offset(off, rs.filter_radius) + Vec2{0.5, 0.5};
      s[j] = CameraSample{};
      s[j].uv = {std::clamp((x + off.x) / width, 0.0, 1.0),
                 std::clamp((y + off.y) / height, 0.0, 1.0)};
    }
    cam.generate_batch(s, m, &rays);
    for (int j = 0; j < m; ++j) covered += rays.valid[j];
  }
  return float(double(covered) / n);
}

}  // namespace

std::vector<float> rim_coverage(const Camera& cam, const RenderSettings& rs, int width, int height,
                                const std::vector<uint8_t>& pixels, int grid) {
  std::vector<float> out(pixels.size(), -1.0f);
  parallel_chunks(0, pixels.size(), 256, [&](size_t lo, size_t hi) {
    for (size_t i = lo; i < hi; ++i)
      if (pixels[i])
        out[i] = pixel_coverage(cam, rs, width, height, int(i % size_t(width)),
                                int(i / size_t(width)), grid);
  });
  return out;
}

}  // namespace anamorph
