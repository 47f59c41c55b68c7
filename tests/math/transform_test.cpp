#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "math/rng.h"
#include "math/transform.h"

namespace anamorph {

TEST(Transform, InverseRoundTrip) {
  const Transform t = Transform::translate({1, 2, 3}) * Transform::rotate(37, {1, 1, 0}) *
                      Transform::scale({2, 0.5, 3});
  const Vec3 p{0.3, -1.2, 4.5};
  const Vec3 q = t.inverse().point(t.point(p));
  EXPECT_NEAR(length(q - p), 0.0, 1e-12) << "q=" << q.x << "," << q.y << "," << q.z;
}

TEST(Transform, NormalsStayPerpendicularUnderNonUniformScale) {
  const Transform t = Transform::rotate(20, {0, 0, 1}) * Transform::scale({3, 1, 0.2});
  const Vec3 tangent{1, 1, 0}, n{1, -1, 0};
  ASSERT_DOUBLE_EQ(dot(tangent, n), 0);
  EXPECT_NEAR(dot(t.vector(tangent), t.normal(n)), 0.0, 1e-12);
}

TEST(Transform, LookAtMapsMinusZToForward) {
  const Vec3 from{1, 2, 3}, at{4, 2, -1};
  const Transform t = Transform::look_at(from, at, {0, 1, 0});
  const Vec3 f = normalize(t.vector({0, 0, -1}));
  const Vec3 want = normalize(at - from);
  EXPECT_NEAR(length(f - want), 0.0, 1e-12);
  EXPECT_NEAR(length(t.point({0, 0, 0}) - from), 0.0, 1e-12);
  // right = f x up must be +x of camera space
  EXPECT_NEAR(length(normalize(t.vector({1, 0, 0})) - normalize(cross(want, Vec3{0, 1, 0}))), 0,
              1e-12);
}

TEST(Rng, SameSeedSameStreamDifferentPixelsDiffer) {
  Rng a = Rng::for_sample(3, 4, 5, 42), b = Rng::for_sample(3, 4, 5, 42),
      c = Rng::for_sample(4, 3, 5, 42);
  for (int i = 0; i < 100; ++i) {
    const uint32_t x = a.next_u32();
    EXPECT_EQ(x, b.next_u32());
  }
  int same = 0;
  Rng a2 = Rng::for_sample(3, 4, 5, 42);
  for (int i = 0; i < 100; ++i) same += a2.next_u32() == c.next_u32();
  EXPECT_LT(same, 3);
}

TEST(Rng, UniformMeanIsHalf) {
  Rng r(1, 2);
  double s = 0;
  const int n = 100000;
  for (int i = 0; i < n; ++i) {
    const double u = r.uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    s += u;
  }
  EXPECT_NEAR(s / n, 0.5, 0.005);
}

}  // namespace anamorph

namespace anamorph {

TEST(Rng, QmcPrefixesAreStratifiedInEveryDimensionPair) {
  // Samples 0..15 of one pixel: for each dimension pair, every elementary interval of area 1/16
  // (16x1, 8x2, 4x4, 2x8, 1x16 cells) holds exactly one point; the 8-sample prefix likewise for
  // area 1/8. Pairs must differ from each other (decorrelated by the scrambling).
  constexpr int kPairs = 6;
  double pts[kPairs][16][2];
  for (uint32_t s = 0; s < 16; ++s) {
    Rng r = Rng::for_sample(7, 9, s, 42);
    r.qmc(s, 0x1234567, 2 * kPairs);
    for (int d = 0; d < kPairs; ++d) r.uniform2(pts[d][s][0], pts[d][s][1]);
  }
  for (int n : {8, 16}) {
    const int m = n == 8 ? 3 : 4;
    for (int d = 0; d < kPairs; ++d)
      for (int kx = 0; kx <= m; ++kx) {
        const int cx = 1 << kx, cy = 1 << (m - kx);
        std::vector<int> count(size_t(cx) * cy, 0);
        for (int s = 0; s < n; ++s) count[int(pts[d][s][1] * cy) * cx + int(pts[d][s][0] * cx)]++;
        for (size_t c = 0; c < count.size(); ++c)
          ASSERT_EQ(count[c], 1) << "pair " << d << ", " << n << " samples, " << cx << "x" << cy
                                 << " cells, cell " << c;
      }
  }
  int same = 0;
  for (int s = 0; s < 16; ++s) same += std::abs(pts[0][s][0] - pts[1][s][0]) < 1e-9;
  EXPECT_LT(same, 2) << "pairs 0 and 1 repeat each other";
  // Beyond the QMC dimensions the stream is the ordinary PCG32 one.
  Rng a = Rng::for_sample(7, 9, 3, 42), b = Rng::for_sample(7, 9, 3, 42);
  a.qmc(3, 0x1234567, 2);
  double x, y;
  a.uniform2(x, y);
  EXPECT_EQ(a.next_u32(), b.next_u32());
}

}  // namespace anamorph
