#include "render/image_metrics.h"

#include "io/image_io.h"

#include <algorithm>
#include <cmath>

namespace anamorph {

ImageMetrics compare_images(const std::vector<float>& a, const std::vector<float>& b, int w,
                            int h) {
  ImageMetrics m;
  const size_t n = size_t(w) * h;
  double se = 0, ae = 0, re = 0, sd = 0;
  std::vector<double> la(n), lb(n);
  for (size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) {
      const double x = a[i * 4 + c], y = b[i * 4 + c];
      se += (x - y) * (x - y);
      const double dx = linear_to_srgb(float(std::clamp(x, 0.0, 1.0))),
                   dy = linear_to_srgb(float(std::clamp(y, 0.0, 1.0)));
      sd += (dx - dy) * (dx - dy);
      ae += std::abs(x - y);
      re += std::abs(x - y) / (std::abs(y) + 0.01);
    }
    // SSIM on displayed luminance (clamped to [0,1]).
    auto lum = [](const float* p) {
      return std::clamp(0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2], 0.0, 1.0);
    };
    la[i] = lum(&a[i * 4]);
    lb[i] = lum(&b[i * 4]);
  }
  m.rmse = std::sqrt(se / (3.0 * n));
  m.rmse_display = std::sqrt(sd / (3.0 * n));
  m.mean_abs = ae / (3.0 * n);
  m.mean_relative = re / (3.0 * n);
  const double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
  const int win = 8;
  double sum = 0;
  int count = 0;
  for (int y0 = 0; y0 + win <= h; y0 += win / 2)
    for (int x0 = 0; x0 + win <= w; x0 += win / 2) {
      double ma = 0, mb = 0;
      for (int y = y0; y < y0 + win; ++y)
        for (int x = x0; x < x0 + win; ++x)
          ma += la[size_t(y) * w + x], mb += lb[size_t(y) * w + x];
      ma /= win * win;
      mb /= win * win;
      double va = 0, vb = 0, cov = 0;
      for (int y = y0; y < y0 + win; ++y)
        for (int x = x0; x < x0 + win; ++x) {
          const double da = la[size_t(y) * w + x] - ma, db = lb[size_t(y) * w + x] - mb;
          va += da * da, vb += db * db, cov += da * db;
        }
      const double k = 1.0 / (win * win - 1);
      va *= k, vb *= k, cov *= k;
      sum += ((2 * ma * mb + c1) * (2 * cov + c2)) / ((ma * ma + mb * mb + c1) * (va + vb + c2));
      ++count;
    }
  if (count) m.ssim = sum / count;
  return m;
}

}  // namespace anamorph
