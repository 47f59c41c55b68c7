#include "math/fast_trig.h"

#include <gtest/gtest.h>

#include <cmath>

namespace anamorph {

// sincos_poly against the C library over the range camera angles use (and well beyond it),
// including quadrant boundaries, where the argument reduction matters most.
TEST(FastTrig, SinCosAgreeWithLibmToAFewUlp) {
  double worst_s = 0, worst_c = 0, at_s = 0, at_c = 0;
  auto check = [&](double x) {
    double s, c;
    sincos_poly(x, &s, &c);
    const double es = std::abs(s - std::sin(x)), ec = std::abs(c - std::cos(x));
    if (es > worst_s) worst_s = es, at_s = x;
    if (ec > worst_c) worst_c = ec, at_c = x;
  };
  for (int i = -200000; i <= 200000; ++i) check(i * 1e-4 * 3.3);  // [-66, 66]
  for (int k = -40; k <= 40; ++k)
    for (double e : {-1e-12, -1e-16, 0.0, 1e-16, 1e-12}) check(k * (M_PI / 4) + e);
  EXPECT_LT(worst_s, 4e-16) << "sine worst at x = " << at_s;
  EXPECT_LT(worst_c, 4e-16) << "cosine worst at x = " << at_c;
}

TEST(FastTrig, ExactAtZeroAndOddSymmetric) {
  double s, c;
  sincos_poly(0, &s, &c);
  EXPECT_EQ(s, 0.0);
  EXPECT_EQ(c, 1.0);
  for (double x : {0.1, 0.7, 1.9, 2.5, 3.0, 5.5}) {
    double s1, c1, s2, c2;
    sincos_poly(x, &s1, &c1);
    sincos_poly(-x, &s2, &c2);
    EXPECT_EQ(s1, -s2) << "x = " << x;
    EXPECT_EQ(c1, c2) << "x = " << x;
  }
}

TEST(FastTrig, ExpAgreesWithLibmToAFewUlp) {
  double worst = 0, at = 0;
  for (int i = -200000; i <= 200000; ++i) {
    const double x = i * 3.5e-4;  // [-70, 70]
    const double e = std::abs(exp_poly(x) - std::exp(x)) / std::exp(x);
    if (e > worst) worst = e, at = x;
  }
  EXPECT_LT(worst, 6e-16) << "relative error worst at x = " << at;
  EXPECT_EQ(exp_poly(0), 1.0);
}

}  // namespace anamorph
