#include <gtest/gtest.h>

#include "io/image_io.h"

namespace anamorph {

TEST(Srgb, KnownValues) {
  EXPECT_NEAR(linear_to_srgb(0.5f), 0.735357f, 1e-6);
  EXPECT_NEAR(srgb_to_linear(0.5f), 0.214041f, 1e-6);
  EXPECT_EQ(linear_to_srgb(0.0f), 0.0f);
  EXPECT_NEAR(linear_to_srgb(1.0f), 1.0f, 1e-7);
  EXPECT_NEAR(srgb_to_linear(1.0f), 1.0f, 1e-7);
  // Linear toe below the knee.
  EXPECT_NEAR(linear_to_srgb(0.001f), 0.01292f, 1e-8);
  EXPECT_NEAR(srgb_to_linear(0.02f), 0.02f / 12.92f, 1e-9);
  // Both pieces meet at the knee (0.0031308 linear, 0.04045 encoded).
  EXPECT_NEAR(linear_to_srgb(0.0031308f), 0.04045f, 1e-6);
  EXPECT_NEAR(srgb_to_linear(0.04045f), 0.0031308f, 1e-7);
}

TEST(Srgb, InverseOfEachOtherAndMonotonic) {
  float prev = -1;
  for (int i = 0; i <= 1000; ++i) {
    const float x = float(i) / 1000.0f;
    const float enc = linear_to_srgb(x);
    EXPECT_NEAR(srgb_to_linear(enc), x, 2e-6) << "x=" << x;
    EXPECT_NEAR(linear_to_srgb(srgb_to_linear(x)), x, 2e-6) << "x=" << x;
    EXPECT_GT(enc, prev) << "x=" << x;
    prev = enc;
  }
}

}  // namespace anamorph
