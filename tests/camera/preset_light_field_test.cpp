// light_field (Looking Glass quilt order, convergence, view cone) and integral (lens grid).
#include <gtest/gtest.h>

#include <cmath>

#include "preset_test_util.h"

namespace anamorph {

using test::angle_deg;
using test::camera;
using test::ray;
using test::str;

namespace {
// Camera at the origin looking along -z at a focal plane 5 units away.
const char* kRig = "look_from = [0, 0, 0]\nlook_at = [0, 0, -5]\n";
// Center of tile (col, row from the top) in a cols x rows grid.
Vec2 tile_center(int col, int row, int cols, int rows) {
  return {(col + 0.5) / cols, (row + 0.5) / rows};
}
}  // namespace

TEST(LightField, QuiltOrderStartsBottomLeftAndEyesMoveRight) {
  const int cols = 5, rows = 9;
  const VirtualCamera cam = camera(
      "light_field", std::string(kRig) + "columns = 5\nrows = 9\nview_cone = 40", {2500, 2700});
  const int n = cols * rows;
  double prev_x = -1e300;
  for (int view = 0; view < n; ++view) {
    // Looking Glass order: view = row_from_bottom * cols + col.
    const int col = view % cols, row = rows - 1 - view / cols;
    const auto r = ray(cam, tile_center(col, row, cols, rows));
    ASSERT_TRUE(r);
    EXPECT_GT(r->org.x, prev_x) << "view " << view << " must be right of view " << view - 1;
    EXPECT_NEAR(r->org.y, 0, 1e-15);
    EXPECT_NEAR(r->org.z, 0, 1e-15);
    // The eye of view i sits at angle -cone/2 + cone i/(n-1) seen from the focal plane center.
    const double expected = -20 + 40.0 * view / (n - 1);
    EXPECT_NEAR(degrees(std::atan(r->org.x / 5)), expected, 1e-12) << "view " << view;
    prev_x = r->org.x;
  }
}

TEST(LightField, ViewsConvergeOnTheSharedFocalPlane) {
  const int cols = 8, rows = 6;
  const ImageInfo img{3360, 3360};
  const VirtualCamera cam = camera("light_field", std::string(kRig) + "fov = 14", img);
  const double tile_aspect = (3360.0 / cols) / (3360.0 / rows);
  for (Vec2 st : {Vec2{0.5, 0.5}, Vec2{0.1, 0.2}, Vec2{0.9, 0.75}, Vec2{0.001, 0.999}}) {
    // Where the ray of tile position st meets the focal plane z = -5, for every view.
    const Vec3 expected{(2 * st.x - 1) * 5 * std::tan(radians(7)) * tile_aspect,
                        (1 - 2 * st.y) * 5 * std::tan(radians(7)), -5};
    for (int row = 0; row < rows; ++row)
      for (int col = 0; col < cols; ++col) {
        const Vec2 uv{(col + st.x) / cols, (row + st.y) / rows};
        const auto r = ray(cam, uv);
        ASSERT_TRUE(r);
        const Vec3 hit = r->org + r->dir * (-5 / r->dir.z);
        EXPECT_LT(length(hit - expected), 1e-12)
            << "tile " << col << "," << row << " st " << str(st) << " hit " << str(hit);
      }
  }
}

TEST(LightField, EveryViewSeesAPointNearTheFocalPlane) {
  const VirtualCamera cam = camera("light_field", kRig, {3360, 3360});
  const auto sols = cam.project({0.05, -0.02, -5.2});
  EXPECT_EQ(sols.size(), 48u) << str(sols);
}

TEST(Integral, LensGridAndElementalFieldOfView) {
  const int cols = 16, rows = 9;
  const VirtualCamera cam =
      camera("integral", "columns = 16\nrows = 9\nwidth = 1.6\nlens_fov = 30", {1600, 900});
  const double pitch = 0.1;  // 1.6 / 16 across, 0.9 / 9 down
  for (int row = 0; row < rows; ++row)
    for (int col = 0; col < cols; ++col) {
      const auto c = ray(cam, tile_center(col, row, cols, rows));
      ASSERT_TRUE(c);
      const Vec3 lens{-0.8 + (col + 0.5) * pitch, 0.45 - (row + 0.5) * pitch, 0};
      EXPECT_LT(length(c->org - lens), 1e-14) << "lens " << col << "," << row;
      EXPECT_LT(angle_deg(c->dir, {0, 0, -1}), 1e-12) << "tile center looks straight ahead";
      // The tile's left and right edges are lens_fov / 2 off axis; right is +x (not flipped).
      const auto right = ray(cam, {(col + 1 - 1e-12) / double(cols), (row + 0.5) / rows});
      EXPECT_NEAR(degrees(std::atan2(right->dir.x, -right->dir.z)), 15, 1e-6);
    }
  // A point in front of the array is seen by every lens within its field of view.
  const auto sols = cam.project({0.0, 0.0, -0.2});
  // tan(15 deg) * 0.2 = 0.0536: lenses whose centers are within that of the point's x and
  // within 0.0536 * (100/100) of its y.
  int expected = 0;
  for (int row = 0; row < rows; ++row)
    for (int col = 0; col < cols; ++col) {
      const double x = -0.8 + (col + 0.5) * pitch, y = 0.45 - (row + 0.5) * pitch;
      if (std::abs(x) / 0.2 <= std::tan(radians(15)) && std::abs(y) / 0.2 <= std::tan(radians(15)))
        ++expected;
    }
  EXPECT_EQ(int(sols.size()), expected) << str(sols);
  EXPECT_GT(expected, 0);
}

}  // namespace anamorph
