// cubemap: face order, un-mirrored "inside" faces with continuous seams, and the "opengl"
// convention checked against OpenGL's cube-map face selection table.
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
const Vec3 kAxes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};

// Image position of face f at face position (s, t) for a cols x rows layout.
Vec2 face_uv(int f, double s, double t, int cols, int rows) {
  return {(f % cols + s) / cols, (f / cols + t) / rows};
}
}  // namespace

TEST(Cubemap, FaceOrderInBothLayoutsAndConventions) {
  for (const char* layout : {"3x2", "6x1"})
    for (const char* conv : {"inside", "opengl"}) {
      const int cols = std::string(layout) == "3x2" ? 3 : 6, rows = 6 / cols;
      const VirtualCamera cam = camera(
          "cubemap", std::string("layout = \"") + layout + "\"\nconvention = \"" + conv + "\"",
          {256 * cols, 256 * rows});
      for (int f = 0; f < 6; ++f) {
        const auto r = ray(cam, face_uv(f, 0.5, 0.5, cols, rows));
        ASSERT_TRUE(r);
        EXPECT_LT(angle_deg(r->dir, kAxes[f]), 1e-12) << layout << " " << conv << " face " << f;
        // Face corners are 90-degree views: corner rays are 54.7 degrees off the axis.
        const auto corner = ray(cam, face_uv(f, 1e-9, 1e-9, cols, rows));
        EXPECT_NEAR(angle_deg(corner->dir, kAxes[f]), degrees(std::acos(1 / std::sqrt(3.0))), 1e-6);
      }
    }
}

TEST(Cubemap, InsideFacesAreUnmirroredAndSeamsMeet) {
  const VirtualCamera cam = camera("cubemap", "", {768, 512});
  const auto dir = [&](int f, double s, double t) { return ray(cam, face_uv(f, s, t, 3, 2))->dir; };
  for (int f = 0; f < 6; ++f) {
    // As a camera looking along the axis: right x up = -forward (like the main camera).
    const Vec3 c = dir(f, 0.5, 0.5), right = dir(f, 0.6, 0.5) - c, up = dir(f, 0.5, 0.4) - c;
    EXPECT_GT(dot(cross(right, up), -kAxes[f]), 0) << "face " << f << " is mirrored";
  }
  // Side faces are upright: the top edge is towards +y.
  for (int f : {0, 1, 4, 5}) EXPECT_GT(dir(f, 0.5, 0).y, 0) << f;
  // Shared edges: front (-Z, 5) right edge = +X (0) left edge, +X right = +Z (4) left, +Z right
  // = -X (1) left, -X right = -Z left; +Y (2) bottom = -Z top; -Y (3) top = -Z bottom.
  const auto same = [&](Vec3 a, Vec3 b) { return angle_deg(a, b) < 1e-6; };
  for (double x : {0.1, 0.5, 0.8}) {
    const double e = 1e-9;  // inside the face despite rounding of (col + s) / cols
    EXPECT_TRUE(same(dir(5, 1 - e, x), dir(0, e, x))) << x;
    EXPECT_TRUE(same(dir(0, 1 - e, x), dir(4, e, x))) << x;
    EXPECT_TRUE(same(dir(4, 1 - e, x), dir(1, e, x))) << x;
    EXPECT_TRUE(same(dir(1, 1 - e, x), dir(5, e, x))) << x;
    EXPECT_TRUE(same(dir(2, x, 1 - e), dir(5, x, e))) << x;
    EXPECT_TRUE(same(dir(3, x, e), dir(5, x, 1 - e))) << x;
  }
}

TEST(Cubemap, OpenGlConventionFollowsTheSpecTable) {
  const VirtualCamera cam =
      camera("cubemap", "layout = \"6x1\"\nconvention = \"opengl\"", {1536, 256});
  Rng rng(8, 8);
  for (int k = 0; k < 200; ++k) {
    const Vec3 d{2 * rng.uniform() - 1, 2 * rng.uniform() - 1, 2 * rng.uniform() - 1};
    // OpenGL 4.6, table 8.19.
    const double ax = std::abs(d.x), ay = std::abs(d.y), az = std::abs(d.z);
    int face;
    double sc, tc, ma;
    if (ax >= ay && ax >= az) {
      face = d.x > 0 ? 0 : 1, sc = d.x > 0 ? -d.z : d.z, tc = -d.y, ma = ax;
    } else if (ay >= az) {
      face = d.y > 0 ? 2 : 3, sc = d.x, tc = d.y > 0 ? d.z : -d.z, ma = ay;
    } else {
      face = d.z > 0 ? 4 : 5, sc = d.z > 0 ? d.x : -d.x, tc = -d.y, ma = az;
    }
    const double s = (sc / ma + 1) / 2, t = (tc / ma + 1) / 2;
    const auto r = ray(cam, face_uv(face, s, t, 6, 1));
    ASSERT_TRUE(r);
    EXPECT_LT(angle_deg(r->dir, d), 1e-9) << "direction " << str(d) << " face " << face;
    const auto sols = cam.project(d * 3.0);
    ASSERT_EQ(sols.size(), 1u);
    EXPECT_LT(length(sols[0] - face_uv(face, s, t, 6, 1)), 1e-12);
  }
}

}  // namespace anamorph
