// pushbroom and crossed_slits: the lines every ray passes through.
#include <gtest/gtest.h>

#include <cmath>

#include "math/rng.h"
#include "preset_test_util.h"

namespace anamorph {

using test::angle_deg;
using test::camera;
using test::ray;
using test::str;

TEST(Pushbroom, PerspectiveDownColumnsParallelAcrossThem) {
  const VirtualCamera cam = camera("pushbroom", "fov = 50\nlength = 6", {1200, 600});
  for (double v : {0.1, 0.5, 0.9}) {
    const auto a = ray(cam, {0.05, v}), b = ray(cam, {0.7, v});
    EXPECT_LT(angle_deg(a->dir, b->dir), 1e-12) << "rows are parallel";
    EXPECT_NEAR(b->org.x - a->org.x, 0.65 * 6, 1e-12) << "origins move along the path";
  }
  for (double u : {0.0, 0.3, 1.0}) {
    const auto top = ray(cam, {u, 0}), bottom = ray(cam, {u, 1});
    EXPECT_LT(length(top->org - bottom->org), 1e-15) << "one origin per column";
    EXPECT_NEAR(angle_deg(top->dir, bottom->dir), 50, 1e-9) << "the column spans fov";
    EXPECT_NEAR(top->dir.x, 0, 1e-15);
  }
}

TEST(CrossedSlits, EveryRayMeetsBothSlits) {
  // Vertical slit: the line x = 0, z = 0 (through look_from); horizontal slit: y = 0 at
  // depth slit_distance (z = -2), in the identity rig.
  for (double th : {2.0, -1.5}) {
    const VirtualCamera cam =
        camera("crossed_slits", "fov = 70\nslit_distance = " + std::to_string(th), {1000, 800});
    Rng rng(6, 1);
    for (int k = 0; k < 50; ++k) {
      const Vec2 uv{rng.uniform(), rng.uniform()};
      const auto r = ray(cam, uv);
      ASSERT_TRUE(r);
      const Vec3 at0 = r->org + r->dir * ((0 - r->org.z) / r->dir.z);
      const Vec3 at1 = r->org + r->dir * ((-th - r->org.z) / r->dir.z);
      EXPECT_NEAR(at0.x, 0, 1e-14) << "misses the vertical slit, uv " << str(uv);
      EXPECT_NEAR(at1.y, 0, 1e-14) << "misses the horizontal slit, uv " << str(uv);
    }
  }
}

TEST(CrossedSlits, ZeroDistanceIsPerspective) {
  const VirtualCamera cs = camera("crossed_slits", "fov = 80\nslit_distance = 0", {1280, 720});
  const VirtualCamera pe = camera("perspective", "fov = 80", {1280, 720});
  for (Vec2 uv : {Vec2{0, 0}, Vec2{0.4, 0.9}, Vec2{1, 0.3}}) {
    const auto a = ray(cs, uv), b = ray(pe, uv);
    EXPECT_LT(angle_deg(a->dir, b->dir), 1e-12) << str(uv);
    EXPECT_LT(length(a->org - b->org), 1e-15) << str(uv);
  }
}

}  // namespace anamorph
