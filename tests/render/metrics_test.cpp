#include <gtest/gtest.h>

#include <cmath>

#include "math/rng.h"
#include "render/image_metrics.h"

namespace anamorph {

TEST(Metrics, AnalyticValues) {
  const int w = 32, h = 32;
  std::vector<float> a(size_t(w) * h * 4), b;
  Rng rng(1, 2);
  for (size_t i = 0; i < a.size(); ++i) a[i] = float(0.2 + 0.5 * rng.uniform());
  const ImageMetrics same = compare_images(a, a, w, h);
  EXPECT_EQ(same.rmse, 0);
  EXPECT_DOUBLE_EQ(same.ssim, 1.0);
  b = a;
  for (size_t i = 0; i < b.size(); ++i) b[i] += 0.1f;
  const ImageMetrics off = compare_images(b, a, w, h);
  EXPECT_NEAR(off.rmse, 0.1, 1e-6);
  EXPECT_NEAR(off.mean_abs, 0.1, 1e-6);
  // A constant offset keeps structure: SSIM stays high; noise destroys it.
  EXPECT_GT(off.ssim, 0.8);
  std::vector<float> noisy = a;
  for (size_t i = 0; i < noisy.size(); ++i) noisy[i] = float(0.2 + 0.5 * rng.uniform());
  EXPECT_LT(compare_images(noisy, a, w, h).ssim, 0.2);
}

}  // namespace anamorph
