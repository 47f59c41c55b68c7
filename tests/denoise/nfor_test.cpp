// The denoiser's parts on their own: the ridge solve, the two-buffer variance, NL-means, the MSE
// estimate and the collaborative regression, each against a value known in closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "denoise/least_squares.h"
#include "denoise/nl_means.h"
#include "denoise/regression.h"
#include "denoise/selection.h"
#include "denoise/variance.h"
#include "synthetic.h"

namespace anamorph::nfor {
namespace {

// Planes of w × h × channels filled by f(channel, x, y).
template <class F>
Planes planes(int w, int h, int channels, F f) {
  Planes p(w, h, channels, nullptr);
  for (int c = 0; c < channels; ++c)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) p.at(c, x, y) = float(f(c, x, y));
  return p;
}

Planes constant(int w, int h, int channels, float v) {
  return planes(w, h, channels, [&](int, int, int) { return v; });
}

double mean_of(const Planes& p, int c, int x0, int y0, int x1, int y1) {
  double s = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) s += p.at(c, x, y);
  return s / double((x1 - x0) * (y1 - y0));
}

// Normal equations of data that a linear model fits exactly give back its coefficients; with a
// ridge, the solution satisfies the regularized system.
TEST(NforLeastSquares, SolvesTheNormalEquations) {
  const int n = 5, rows = 40;
  const double truth[n][2] = {{0.5, -1}, {2, 0.25}, {-1, 3}, {0.125, 0}, {4, -2}};
  double m[n * n] = {}, rhs[n * 2] = {};
  for (int i = 0; i < rows; ++i) {
    double x[n] = {1};
    for (int a = 1; a < n; ++a) x[a] = test::gaussian(3, uint64_t(i * n + a));
    for (int r = 0; r < 2; ++r) {
      double y = 0;
      for (int a = 0; a < n; ++a) y += x[a] * truth[a][r];
      for (int a = 0; a < n; ++a) rhs[a * 2 + r] += x[a] * y;
    }
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b) m[a * n + b] += x[a] * x[b];
  }
  double beta[n * 2];
  ASSERT_TRUE(solve_ridge(n, m, rhs, 2, 0.0, beta));
  for (int a = 0; a < n; ++a)
    for (int r = 0; r < 2; ++r) EXPECT_NEAR(beta[a * 2 + r], truth[a][r], 1e-12) << a << "," << r;
  ASSERT_TRUE(solve_ridge(n, m, rhs, 2, 0.1, beta));
  for (int a = 0; a < n; ++a)
    for (int r = 0; r < 2; ++r) {
      double lhs = (a > 0 ? 0.1 * m[0] : 0.0) * beta[a * 2 + r];
      for (int b = 0; b < n; ++b) lhs += m[a * n + b] * beta[b * 2 + r];
      EXPECT_NEAR(lhs, rhs[a * 2 + r], 1e-9) << a << "," << r;
    }
  double zero[n * n] = {};
  EXPECT_FALSE(solve_ridge(n, zero, rhs, 2, 0.1, beta)) << "no weight: nothing to fit";
}

// (a - b)²/2 over independent halves of standard deviation s estimates s², and s²/α where the
// pixels are covered by a fraction α (their straight colours average fewer samples).
TEST(NforVariance, TwoBufferEstimateIsUnbiased) {
  const int w = 128, h = 128;
  const double s = 0.3;
  const auto cover = [](int x, int) { return x < 64 ? 1.0 : 0.25; };
  const auto noise = [&](uint64_t seed) {
    return planes(w, h, 1, [&](int, int x, int y) {
      return 0.5 + s / std::sqrt(cover(x, y)) * test::gaussian(seed, uint64_t(y * w + x));
    });
  };
  const Planes a = noise(1), b = noise(2);
  const Planes cov = planes(w, h, 1, [&](int, int x, int y) { return cover(x, y); });
  Planes var(w, h, 1, nullptr);
  two_buffer_variance(a, b, cov, VarianceEstimate{}, var, nullptr);
  // 60 × 128 pixels, one degree of freedom each: a standard error of 1.6% of the mean.
  EXPECT_NEAR(mean_of(var, 0, 0, 0, 60, h) / (s * s), 1.0, 0.06);
  EXPECT_NEAR(mean_of(var, 0, 68, 0, 128, h) / (s * s / 0.25), 1.0, 0.06);
}

// With a noise-free guide (variance 0) every other patch differs, so NL-means leaves the image
// as it is, bit for bit; a constant image stays constant under any guide; uncovered pixels
// come out 0.
TEST(NforNlMeans, KeepsWhatItShould) {
  const int w = 40, h = 40;
  const Planes ramp = planes(w, h, 1, [](int, int x, int y) { return 0.01 * x + 0.003 * y * y; });
  const Planes zero = constant(w, h, 1, 0.0f), full = constant(w, h, 1, 1.0f);
  Planes out(w, h, 1, nullptr);
  const Planes* in[] = {&ramp};
  Planes* o[] = {&out};
  nl_means({&ramp, &zero, &full}, {3, 0.5f}, 5, in, o, nullptr);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) ASSERT_EQ(out.at(0, x, y), ramp.at(0, x, y)) << x << "," << y;

  const Planes noisy = planes(w, h, 1, [](int, int x, int y) {
    return 0.5 + 0.2 * test::gaussian(9, uint64_t(y * 40 + x));
  });
  const Planes var = constant(w, h, 1, 0.04f), flat = constant(w, h, 1, 0.25f);
  const Planes disc = planes(w, h, 1, [](int, int x, int y) {
    return (x - 20) * (x - 20) + (y - 20) * (y - 20) < 300 ? 1.0 : 0.0;
  });
  const Planes* in2[] = {&flat};
  nl_means({&noisy, &var, &disc}, {3, 1.0f}, 7, in2, o, nullptr);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      ASSERT_NEAR(out.at(0, x, y), disc.at(0, x, y) > 0 ? 0.25f : 0.0f, 1e-6f) << x << "," << y;
}

// For the filter that changes nothing (fa = a, fb = b) the mean of the halves has MSE s²/2,
// which the estimate recovers on average.
TEST(NforSelection, MseEstimateIsUnbiased) {
  const int w = 128, h = 128;
  const double s = 0.2;
  const auto noise = [&](uint64_t seed) {
    return planes(w, h, 3, [&](int c, int x, int y) {
      return 0.4 + s * test::gaussian(seed, uint64_t((c * h + y) * w + x));
    });
  };
  Candidate f{noise(1), noise(2)};
  const Planes var = constant(w, h, 3, float(s * s)), cov = constant(w, h, 1, 1.0f);
  Planes mse(w, h, 3, nullptr);
  estimate_mse(f.a, f.b, var, var, f, cov, mse);
  for (int c = 0; c < 3; ++c)  // 16384 pixels: a standard error of 1.3% of the mean
    EXPECT_NEAR(mean_of(mse, c, 0, 0, w, h) / (s * s / 2), 1.0, 0.06) << "channel " << c;
}

// A colour affine in the features and the pixel position is reproduced by the regression with
// any weights: here from an unrelated noisy guide, over a coverage with holes. Without a ridge
// to float rounding (measured 6e-6); the default ridge (1e-3) shrinks the standardized slopes
// by about 0.1%, an error of about 1e-3 of the colour's range (2.4 here; measured 1.2e-3).
TEST(NforRegression, ExactForAColourAffineInTheRegressors) {
  const int w = 48, h = 40;
  const Planes features = planes(w, h, 2, [](int c, int x, int y) {
    return c == 0 ? ((x / 7 + y / 5) % 3) * 0.4 : std::sin(0.3 * x) + 0.1 * y;
  });
  const Planes color = planes(w, h, 3, [&](int c, int x, int y) {
    return 0.2 + 0.1 * c + (0.5 - 0.2 * c) * features.at(0, x, y) + 0.3 * features.at(1, x, y) +
           0.004 * x - 0.002 * c * y;
  });
  const Planes guide = planes(w, h, 3, [](int c, int x, int y) {
    return test::gaussian(4, uint64_t((c * 40 + y) * 48 + x));
  });
  const Planes var = constant(w, h, 3, 1.0f);
  const Planes cov =
      planes(w, h, 1, [](int, int x, int y) { return (x * 7 + y * 3) % 11 ? 1.0 : 0.0; });
  RegressionInput in;
  in.color = &color;
  in.guide = {&guide, &var, &cov};
  in.features = &features;
  in.bandwidths = {0.5f, 2.0f};
  for (float ridge : {0.0f, 1e-3f}) {
    in.ridge = ridge;
    Planes a(w, h, 3, nullptr), b(w, h, 3, nullptr);
    Planes* out[] = {&a, &b};
    collaborative_regression(in, out, nullptr, nullptr);
    double worst = 0;
    for (const Planes* p : {&a, &b})
      for (int c = 0; c < 3; ++c)
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x) {
            const float want = cov.at(0, x, y) > 0 ? color.at(c, x, y) : 0.0f;
            worst = std::max(worst, double(std::fabs(p->at(c, x, y) - want)));
          }
    EXPECT_LT(worst, ridge > 0 ? 2.4e-3 : 1e-4) << "ridge " << ridge;
  }
}

}  // namespace
}  // namespace anamorph::nfor
