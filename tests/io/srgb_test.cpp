#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

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

// The table-driven 8-bit encoding gives exactly the clamped, rounded encoded value: around every
// code boundary, on a dense sweep, and for out-of-range inputs.
TEST(Srgb, EightBitCodesMatchRoundedEncoding) {
  const auto reference = [](float v) {
    const float e = linear_to_srgb(v);
    const float c = e > 0.0f ? std::min(e, 1.0f) : 0.0f;
    return int(std::lround(c * 255.0f));
  };
  int mismatches = 0;
  const auto check = [&](float v) {
    if (int(linear_to_srgb8(v)) != reference(v) && ++mismatches <= 5)
      ADD_FAILURE() << "v=" << v << ": table " << int(linear_to_srgb8(v)) << ", reference "
                    << reference(v);
  };
  for (int k = 0; k <= 255; ++k) {
    // The linear value at each half-code boundary, and its float neighbours.
    float v = srgb_to_linear((k + 0.5f) / 255.0f);
    for (int step = 0; step < 4; ++step) v = std::nextafter(v, 0.0f);
    for (int step = 0; step < 8; ++step, v = std::nextafter(v, 2.0f)) check(v);
  }
  for (int i = 0; i <= 1000000; ++i) check(float(i) / 1000000.0f);
  for (float v :
       {-1.0f, -0.0f, 0.0f, 1e-30f, 1.0f, 1.5f, 1e30f, std::numeric_limits<float>::infinity(),
        -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN()})
    check(v);
  EXPECT_EQ(mismatches, 0);
}

}  // namespace anamorph
