// io/mip_texture.h: bilinear lookups exact on a linear ramp, the area filter equal to bilinear
// where a pixel's footprint is within a texel, a minified pattern averaged instead of aliased,
// and the two ways outside the image (u wrapping around, black).
#include "io/mip_texture.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace anamorph {
namespace {

// An RGBA image whose red channel is f(x, y) at pixel centers.
template <class F>
Image image_of(int w, int h, F f) {
  Image img;
  img.width = w, img.height = h, img.channels = 4;
  img.pixels.resize(size_t(w) * size_t(h) * 4);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float* p = &img.pixels[(size_t(y) * size_t(w) + size_t(x)) * 4];
      p[0] = float(f(x, y)), p[1] = 0, p[2] = 0, p[3] = 1;
    }
  return img;
}

TEST(MipTexture, BilinearIsExactOnARampAndAreaEqualsItWithinATexel) {
  const int W = 64, H = 32;
  const MipTexture t(image_of(W, H, [](int x, int y) { return 0.25 * x + 0.5 * y; }), false);
  EXPECT_EQ(t.levels(), 7);  // 64x32, 32x16, ..., 1x1
  for (double px : {3.0, 10.25, 31.5, 50.9})
    for (double py : {2.0, 7.75, 20.5}) {
      const Vec2 uv{(px + 0.5) / W, (py + 0.5) / H};
      float b[4], a[4];
      t.bilinear(uv, b);
      EXPECT_NEAR(b[0], 0.25 * px + 0.5 * py, 1e-4) << "at pixel " << px << ", " << py;
      // A footprint of 0.9 x 0.6 texels, rotated: level 0, the same bilinear lookup.
      t.area(uv, {0.6 / W, 0.6 / H}, {-0.4 / W, 0.3 / H}, a);
      for (int c = 0; c < 4; ++c) EXPECT_EQ(a[c], b[c]) << "channel " << c;
    }
}

// Columns alternating 0 and 1 looked up where a target pixel covers 4, 12 and 40 texels along
// u: the area filter gives the mean 0.5 everywhere (within 0.07); bilinear lookups at the same
// places alias (0 or 1 depending on where they land).
TEST(MipTexture, AMinifiedPatternIsAveragedNotAliased) {
  const int W = 512, H = 16;
  const MipTexture t(image_of(W, H, [](int x, int) { return x % 2; }), true);
  for (double texels : {4.0, 12.0, 40.0}) {
    double lo = 1, hi = 0, blo = 1, bhi = 0;
    for (int i = 0; i < 97; ++i) {
      const Vec2 uv{(i * 5.3 + 0.5) / W, 0.5};
      float a[4], b[4];
      t.area(uv, {texels / W, 0}, {0, 1.0 / H}, a);
      t.bilinear(uv, b);
      lo = std::min(lo, double(a[0])), hi = std::max(hi, double(a[0]));
      blo = std::min(blo, double(b[0])), bhi = std::max(bhi, double(b[0]));
    }
    EXPECT_GT(lo, 0.43) << texels << " texels a pixel: area filter's range " << lo << ".." << hi;
    EXPECT_LT(hi, 0.57) << texels << " texels a pixel: area filter's range " << lo << ".." << hi;
    EXPECT_GT(bhi - blo, 0.8) << "bilinear's range " << blo << ".." << bhi;
  }
}

TEST(MipTexture, OutsideTheImageUWrapsOrIsBlack) {
  const int W = 8, H = 4;
  const auto column = [](int x, int) { return 1.0 + x; };
  const MipTexture wraps(image_of(W, H, column), true), black(image_of(W, H, column), false);
  float a[4], b[4];
  // u = 0: half way between the last column's center and the first's.
  wraps.bilinear({0, 0.5}, a);
  black.bilinear({0, 0.5}, b);
  EXPECT_FLOAT_EQ(a[0], 0.5f * (1 + 8));
  EXPECT_FLOAT_EQ(a[3], 1);
  EXPECT_FLOAT_EQ(b[0], 0.5f * 1);  // (and half the alpha: black is 0 in all four channels)
  EXPECT_FLOAT_EQ(b[3], 0.5f);
  // v above the image: clamped to the top row when u wraps (an equirect's pole), else black.
  wraps.bilinear({2.5 / W, -0.5}, a);
  black.bilinear({2.5 / W, -0.5}, b);
  EXPECT_FLOAT_EQ(a[0], 3);
  EXPECT_FLOAT_EQ(b[0], 0);
}

}  // namespace
}  // namespace anamorph
