// Depth of field for any camera: aperture 0 is exactly the pinhole ray; otherwise every ray
// passes through the pinhole ray's point at focus_distance, leaving from the aperture disk.
#include <gtest/gtest.h>

#include <cstring>

#include "camera/presets.h"
#include "math/rng.h"

namespace anamorph {

namespace {
const char* kCases[][2] = {{"perspective", "fov = 50"},
                           {"fisheye", "fov = 200"},
                           {"equirectangular", ""},
                           {"ods", ""},
                           {"cylindrical", ""}};
}  // namespace

TEST(DepthOfField, ApertureZeroIsThePinholeRayBitForBit) {
  for (const auto& c : kCases) {
    const VirtualCamera pin(make_preset(c[0], c[1], {64, 48}));
    const VirtualCamera dof(make_preset(c[0], c[1], {64, 48}), DepthOfField{0.0, 3.0});
    Rng rng(7, 1);
    for (int i = 0; i < 200; ++i) {
      CameraSample s;
      s.uv = {rng.uniform(), rng.uniform()};
      s.lens = {rng.uniform(), rng.uniform()};
      const auto a = pin.generate(s), b = dof.generate(s);
      ASSERT_EQ(bool(a), bool(b)) << c[0];
      if (!a) continue;
      EXPECT_EQ(0, std::memcmp(&*a, &*b, sizeof(CameraRay)))
          << c[0] << " at " << s.uv.x << "," << s.uv.y;
    }
  }
}

TEST(DepthOfField, RaysMeetAtTheFocusDistance) {
  for (const auto& c : kCases) {
    const double focus = 4.0, aperture = 0.2;
    const VirtualCamera pin(make_preset(c[0], c[1], {64, 48}));
    const VirtualCamera dof(make_preset(c[0], c[1], {64, 48}), DepthOfField{aperture, focus});
    Rng rng(3, 9);
    for (int i = 0; i < 200; ++i) {
      CameraSample s;
      s.uv = {rng.uniform(), rng.uniform()};
      s.lens = {rng.uniform(), rng.uniform()};
      const auto p = pin.generate(s), r = dof.generate(s);
      if (!p) continue;
      ASSERT_TRUE(r);
      const Vec3 target = p->org + p->dir * focus;
      const Vec3 offset = r->org - p->org;
      EXPECT_LE(length(offset), aperture * (1 + 1e-12)) << c[0];
      EXPECT_NEAR(dot(offset, p->dir), 0, 1e-12)
          << c[0] << ": the lens disk is perpendicular to the ray";
      // The DOF ray passes through the pinhole ray's point at the focus distance.
      const Vec3 to = target - r->org;
      EXPECT_NEAR(length(to - r->dir * dot(to, r->dir)), 0, 1e-9) << c[0];
      EXPECT_NEAR(length(r->dir), 1, 1e-12);
    }
  }
}

}  // namespace anamorph
