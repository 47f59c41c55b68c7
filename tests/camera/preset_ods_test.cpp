// ods: eye origins on the circle, tangent rays, mirrored eyes, layouts and pole merging.
#include <gtest/gtest.h>

#include <cmath>

#include "math/rng.h"
#include "preset_test_util.h"

namespace anamorph {

using test::angle_deg;
using test::camera;
using test::ray;
using test::str;

namespace {
// World frame of kRig-like settings used below: center (1, 2, 3), identity orientation.
const Vec3 kCenter{1, 2, 3};
const char* kRig = "look_from = [1, 2, 3]\nlook_at = [1, 2, -1]\n";
}  // namespace

TEST(Ods, OriginsOnTheCircleRaysTangentEyesMirrored) {
  const double ipd = 0.064;
  const VirtualCamera cam = camera("ods", std::string(kRig) + "ipd = 0.064", {2048, 2048});
  Rng rng(2, 3);
  for (int k = 0; k < 100; ++k) {
    // A position in the left (top) half and the same position in the right (bottom) half.
    const Vec2 l{rng.uniform(), 0.5 * rng.uniform()}, r{l.x, l.y + 0.5};
    const auto a = ray(cam, l), b = ray(cam, r);
    ASSERT_TRUE(a && b);
    const Vec3 oa = a->org - kCenter, ob = b->org - kCenter;
    EXPECT_NEAR(oa.y, 0, 1e-15) << "origins in the horizontal plane";
    EXPECT_NEAR(length(oa), ipd / 2, 1e-15) << "on the circle, uv " << str(l);
    EXPECT_NEAR(length(ob), ipd / 2, 1e-15);
    // Tangent: the origin's radius is perpendicular to the ray's horizontal direction.
    EXPECT_NEAR(dot(oa, a->dir), 0, 1e-15)
        << "uv " << str(l) << " org " << str(oa) << " dir " << str(a->dir);
    EXPECT_LT(length(oa + ob), 1e-15) << "the eyes are mirrored through the center";
    EXPECT_LT(angle_deg(a->dir, b->dir), 1e-12) << "both eyes look the same way";
  }
  // Looking forward (lon 0), the right eye sits to the right (+x) and the left eye to the left.
  EXPECT_NEAR(ray(cam, {0.5, 0.75})->org.x - kCenter.x, ipd / 2, 1e-15);
  EXPECT_NEAR(ray(cam, {0.5, 0.25})->org.x - kCenter.x, -ipd / 2, 1e-15);
  // Looking right (lon 90), the right eye sits behind (+z).
  EXPECT_NEAR(ray(cam, {0.75, 0.75})->org.z - kCenter.z, ipd / 2, 1e-15);
}

TEST(Ods, SideBySideLayout) {
  const VirtualCamera cam =
      camera("ods", std::string(kRig) + "layout = \"side_by_side\"", {4096, 1024});
  const auto left = ray(cam, {0.25, 0.5}), right = ray(cam, {0.75, 0.5});
  EXPECT_LT(left->org.x, kCenter.x) << "left half = left eye";
  EXPECT_GT(right->org.x, kCenter.x);
  EXPECT_LT(angle_deg(left->dir, {0, 0, -1}), 1e-12);
  EXPECT_LT(angle_deg(right->dir, {0, 0, -1}), 1e-12);
}

TEST(Ods, PoleMergeShrinksTheCircleBetweenTheLatitudes) {
  const double ipd = 0.2;
  const VirtualCamera cam =
      camera("ods", std::string(kRig) + "ipd = 0.2\npole_merge = [60, 80]", {1800, 1800});
  // Top half, left eye: v in [0, 0.5) covers latitude 90 .. -90.
  const auto radius_at = [&](double lat) {
    const double v = 0.5 * (90 - lat) / 180;
    return length(ray(cam, {0.3, v})->org - kCenter);
  };
  for (double lat : {0.0, 45.0, 59.9, -60.0}) EXPECT_NEAR(radius_at(lat), ipd / 2, 1e-15) << lat;
  for (double lat : {80.0, 85.0, -81.0, 89.9}) EXPECT_NEAR(radius_at(lat), 0, 1e-15) << lat;
  double prev = ipd / 2;
  for (double lat = 61; lat < 80; lat += 1) {
    const double r = radius_at(lat);
    EXPECT_LT(r, prev) << "decreasing at " << lat;
    EXPECT_GT(r, 0) << lat;
    prev = r;
  }
  EXPECT_NEAR(radius_at(70), ipd / 4, 1e-12) << "smoothstep is 1/2 half way";
}

TEST(Ods, NearPointsHaveParallax) {
  const VirtualCamera cam = camera("ods", std::string(kRig) + "ipd = 0.064", {2048, 2048});
  const auto sols = cam.project(kCenter + Vec3{0.1, 0.05, -0.5});
  ASSERT_EQ(sols.size(), 2u) << str(sols);
  const Vec2 left = sols[0].y < 0.5 ? sols[0] : sols[1],
             right = sols[0].y < 0.5 ? sols[1] : sols[0];
  EXPECT_LT(left.y, 0.5);
  EXPECT_GE(right.y, 0.5);
  // The left eye sees a point ahead further to the right (larger u) than the right eye does.
  EXPECT_GT(left.x - right.x, 1e-3);
  // Inside the eye circle nothing is seen.
  EXPECT_TRUE(cam.project(kCenter + Vec3{0.01, 0, 0}).empty());
}

}  // namespace anamorph
