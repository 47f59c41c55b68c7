#include <gtest/gtest.h>

#include <cmath>

#include "camera/presets.h"

namespace anamorph {

namespace {
ParamValues look_at_values(double fov, const std::string& axis) {
  ParamValues v;
  v.set("look_from", Vec3{1, 2, 3});
  v.set("look_at", Vec3{1, 2, -7});
  v.set("up", Vec3{0, 1, 0});
  v.set("fov", fov);
  v.set("fov_axis", axis);
  v.set("lens_shift", Vec2{0, 0});
  return v;
}
VirtualCamera make(double fov, const std::string& axis, ImageInfo img) {
  return VirtualCamera(find_preset("perspective")->create(look_at_values(fov, axis), img));
}
}  // namespace

TEST(Perspective, CenterLooksAtTarget) {
  const VirtualCamera cam = make(60, "horizontal", {640, 480});
  const auto r = cam.generate({{0.5, 0.5}});
  ASSERT_TRUE(r);
  EXPECT_NEAR(length(r->dir - Vec3{0, 0, -1}), 0, 1e-12);
  EXPECT_NEAR(length(r->org - Vec3{1, 2, 3}), 0, 1e-12);
}

TEST(Perspective, EdgesSpanFov) {
  for (const char* axis : {"horizontal", "vertical", "diagonal"}) {
    const VirtualCamera cam = make(70, axis, {640, 480});
    Vec2 a{0, 0.5}, b{1, 0.5};
    if (std::string(axis) == "vertical") a = {0.5, 0}, b = {0.5, 1};
    if (std::string(axis) == "diagonal") a = {0, 0}, b = {1, 1};
    const auto ra = cam.generate({a}), rb = cam.generate({b});
    ASSERT_TRUE(ra && rb);
    const double angle = degrees(std::acos(dot(ra->dir, rb->dir)));
    EXPECT_NEAR(angle, 70, 1e-9) << axis;
  }
}

TEST(Perspective, UpIsUpAndRightIsRight) {
  const VirtualCamera cam = make(60, "horizontal", {100, 100});
  const auto top = cam.generate({{0.5, 0.0}}), right = cam.generate({{1.0, 0.5}});
  EXPECT_GT(top->dir.y, 0);    // v = 0 is the top of the image
  EXPECT_GT(right->dir.x, 0);  // looking down -z with +y up, +x is to the right
}

TEST(Perspective, DifferentialsMatchFiniteDifferences) {
  const VirtualCamera cam = make(50, "horizontal", {320, 200});
  const Vec2 uv{0.3, 0.7};
  const double h = 1e-6;
  const auto r = cam.generate({uv}), ru = cam.generate({{uv.x + h, uv.y}}),
             rv = cam.generate({{uv.x, uv.y + h}});
  const Vec3 fdu = (ru->dir - r->dir) / h, fdv = (rv->dir - r->dir) / h;
  EXPECT_NEAR(length(fdu - r->ddir_du), 0, 1e-5);
  EXPECT_NEAR(length(fdv - r->ddir_dv), 0, 1e-5);
}

TEST(Perspective, LensShiftMovesTheWindow) {
  // Shift (0.1, -0.2) of a 2t x 2t/a window at distance 1: the center ray goes through
  // (0.1 w, -0.2 h, -1) in camera space.
  ParamValues v = look_at_values(90, "horizontal");
  v.set("lens_shift", Vec2{0.1, -0.2});
  const ImageInfo img{400, 200};
  const VirtualCamera cam(find_preset("perspective")->create(v, img));
  const double w = 2 * std::tan(radians(45)), h = w / img.aspect();
  const auto r = cam.generate({{0.5, 0.5}});
  ASSERT_TRUE(r);
  EXPECT_NEAR(length(r->dir - normalize(Vec3{0.1 * w, -0.2 * h, -1})), 0, 1e-12);
  // The edges are no longer symmetric: the left edge is 0.4 w left, the right 0.6 w right.
  EXPECT_NEAR(cam.generate({{0, 0.5}})->dir.x / -cam.generate({{0, 0.5}})->dir.z, -0.4 * w, 1e-12);
  EXPECT_NEAR(cam.generate({{1, 0.5}})->dir.x / -cam.generate({{1, 0.5}})->dir.z, 0.6 * w, 1e-12);
}

TEST(Perspective, ProjectRoundTrip) {
  const VirtualCamera cam = make(60, "horizontal", {640, 480});
  const Vec2 uv{0.23, 0.81};
  const auto r = cam.generate({uv});
  const Vec3 p = r->org + r->dir * 7.5;
  const auto sols = cam.project(p);
  ASSERT_EQ(sols.size(), 1u);
  EXPECT_NEAR(sols[0].x, uv.x, 1e-9);
  EXPECT_NEAR(sols[0].y, uv.y, 1e-9);
  EXPECT_TRUE(cam.project(Vec3{1, 2, 10}).empty()) << "a point behind the camera is not visible";
}

}  // namespace anamorph
