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
