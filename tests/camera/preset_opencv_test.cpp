// opencv_pinhole and opencv_fisheye against OpenCV's published projection equations, computed
// here by hand (cv::projectPoints and cv::fisheye::projectPoints documentation), in OpenCV's
// camera frame (X right, Y down, Z forward) and pixel convention (pixel centers at integers).
#include <gtest/gtest.h>

#include <cmath>

#include "preset_test_util.h"

namespace anamorph {

using test::angle_deg;
using test::camera;
using test::ray;
using test::str;

namespace {

struct Pinhole {
  double fx, fy, cx, cy, k1, k2, k3, p1, p2;
};
// cv::projectPoints for a point in OpenCV camera coordinates.
Vec2 opencv_project(const Pinhole& c, const Vec3& P) {
  const double x = P.x / P.z, y = P.y / P.z;
  const double r2 = x * x + y * y;
  const double radial = 1 + c.k1 * r2 + c.k2 * r2 * r2 + c.k3 * r2 * r2 * r2;
  const double xd = x * radial + 2 * c.p1 * x * y + c.p2 * (r2 + 2 * x * x);
  const double yd = y * radial + c.p1 * (r2 + 2 * y * y) + 2 * c.p2 * x * y;
  return {c.fx * xd + c.cx, c.fy * yd + c.cy};
}

struct Fisheye {
  double fx, fy, cx, cy, k1, k2, k3, k4;
};
// cv::fisheye::projectPoints (alpha = 0).
Vec2 opencv_fisheye_project(const Fisheye& c, const Vec3& P) {
  const double a = P.x / P.z, b = P.y / P.z;
  const double r = std::sqrt(a * a + b * b);
  const double th = std::atan(r);
  const double th2 = th * th;
  const double thd = th * (1 + c.k1 * th2 + c.k2 * th2 * th2 + c.k3 * th2 * th2 * th2 +
                           c.k4 * th2 * th2 * th2 * th2);
  const double xd = r > 0 ? thd / r * a : 0, yd = r > 0 ? thd / r * b : 0;
  return {c.fx * xd + c.cx, c.fy * yd + c.cy};
}

std::string num(double x) {
  char b[64];
  std::snprintf(b, sizeof b, "%.17g", x);
  return b;
}

// Camera at the origin looking along -z (ours), i.e. OpenCV frame (x, -y, -z).
Vec3 ours_from_opencv(const Vec3& P) { return {P.x, -P.y, -P.z}; }

const ImageInfo kImg{1920, 1080};

// Our projection of a world point as OpenCV pixel coordinates.
std::vector<Vec2> pixels(const Camera& cam, const Vec3& p) {
  std::vector<Vec2> out;
  for (const Vec2& uv : cam.project(p))
    out.push_back({uv.x * kImg.width - 0.5, uv.y * kImg.height - 0.5});
  return out;
}

const Vec3 kPoints[] = {{0, 0, 5},       {0.3, -0.2, 2},    {-1.1, 0.6, 3.5},
                        {0.9, 0.5, 1.7}, {-0.4, -0.3, 1.2}, {2.0, 1.0, 4.0}};

}  // namespace

TEST(OpenCvPinhole, MatchesOpenCvEquations) {
  const Pinhole c{1400, 1390, 955.25, 545.75, -0.28, 0.09, -0.01, 0.001, -0.0005};
  const std::string toml = "fx = " + num(c.fx) + "\nfy = " + num(c.fy) + "\ncx = " + num(c.cx) +
                           "\ncy = " + num(c.cy) + "\nk1 = " + num(c.k1) + "\nk2 = " + num(c.k2) +
                           "\nk3 = " + num(c.k3) + "\np1 = " + num(c.p1) + "\np2 = " + num(c.p2);
  const VirtualCamera cam = camera("opencv_pinhole", toml, kImg);
  for (const Vec3& P : kPoints) {
    const Vec2 expected = opencv_project(c, P);
    const Vec3 p = ours_from_opencv(P);
    const auto got = pixels(cam, p);
    ASSERT_EQ(got.size(), 1u) << "OpenCV point " << str(P) << " expected pixel " << str(expected);
    EXPECT_LT(length(got[0] - expected), 1e-6) << "OpenCV point " << str(P) << " expected pixel "
                                               << str(expected) << " got " << str(got[0]);
    // The ray of that pixel (undistorted by Newton) passes through the point.
    const auto r = ray(cam, {(expected.x + 0.5) / kImg.width, (expected.y + 0.5) / kImg.height});
    ASSERT_TRUE(r);
    EXPECT_LT(angle_deg(r->dir, p), 1e-9)
        << "ray of pixel " << str(expected) << " dir " << str(r->dir);
  }
}

TEST(OpenCvPinhole, PixelCentersAreIntegers) {
  // No distortion, principal point at the image center (W - 1) / 2: the center of pixel column
  // i looks along x/z = (i - cx) / fx.
  const VirtualCamera cam = camera("opencv_pinhole", "fx = 1000\nfy = 1000", kImg);
  const double cx = (kImg.width - 1) / 2.0, cy = (kImg.height - 1) / 2.0;
  for (int i : {0, 17, 959, 960, 1919})
    for (int j : {0, 539, 1079}) {
      const auto r = ray(cam, {(i + 0.5) / kImg.width, (j + 0.5) / kImg.height});
      ASSERT_TRUE(r);
      EXPECT_NEAR(r->dir.x / -r->dir.z, (i - cx) / 1000, 1e-14) << "column " << i;
      EXPECT_NEAR(-r->dir.y / -r->dir.z, (j - cy) / 1000, 1e-14) << "row " << j;
    }
}

TEST(OpenCvPinhole, CalibrationSizeScalesToOtherResolutions) {
  const std::string k = "fx = 1400\nfy = 1390\ncx = 955.25\ncy = 545.75\nk1 = -0.2\np1 = 0.001";
  const VirtualCamera full = camera("opencv_pinhole", k, kImg);
  const VirtualCamera half =
      camera("opencv_pinhole", k + "\ncalibration_size = [1920, 1080]", {960, 540});
  for (Vec2 uv : {Vec2{0.1, 0.2}, Vec2{0.5, 0.5}, Vec2{0.87, 0.66}}) {
    const auto a = ray(full, uv), b = ray(half, uv);
    ASSERT_TRUE(a && b);
    EXPECT_LT(angle_deg(a->dir, b->dir), 1e-12) << "uv " << str(uv);
  }
  EXPECT_THROW(make_preset("opencv_pinhole", k + "\ncalibration_size = [1920, 1200]", {960, 540}),
               ParamError);
}

TEST(OpenCvPinhole, BeyondTheFoldThereIsNoRay) {
  // k1 = -0.5: r L(r) = r - 0.5 r^3 peaks at r = sqrt(2/3); wider pixels have no preimage.
  const VirtualCamera cam = camera("opencv_pinhole", "fx = 500\nfy = 500\nk1 = -0.5", kImg);
  EXPECT_FALSE(ray(cam, {0, 0.5})) << "x'' = -1.92 exceeds the fold's 0.544";
  EXPECT_TRUE(ray(cam, {0.5 - 0.5 * 500 / 1920.0, 0.5})) << "x'' = -0.5 is inside";
  EXPECT_TRUE(cam.project(Vec3{0.9, 0, -1}).empty()) << "x' = 0.9 beyond the fold at 0.816";
  EXPECT_EQ(cam.project(Vec3{0.7, 0, -1}).size(), 1u);
}

TEST(OpenCvFisheye, MatchesOpenCvEquations) {
  const Fisheye c{600, 602, 950.5, 530.25, 0.05, -0.01, 0.002, -0.0003};
  const std::string toml = "fx = " + num(c.fx) + "\nfy = " + num(c.fy) + "\ncx = " + num(c.cx) +
                           "\ncy = " + num(c.cy) + "\nk1 = " + num(c.k1) + "\nk2 = " + num(c.k2) +
                           "\nk3 = " + num(c.k3) + "\nk4 = " + num(c.k4);
  const VirtualCamera cam = camera("opencv_fisheye", toml, kImg);
  for (const Vec3& P : kPoints) {
    const Vec2 expected = opencv_fisheye_project(c, P);
    const Vec3 p = ours_from_opencv(P);
    const auto got = pixels(cam, p);
    ASSERT_EQ(got.size(), 1u) << "OpenCV point " << str(P) << " expected pixel " << str(expected);
    EXPECT_LT(length(got[0] - expected), 1e-6) << "OpenCV point " << str(P) << " expected pixel "
                                               << str(expected) << " got " << str(got[0]);
    const auto r = ray(cam, {(expected.x + 0.5) / kImg.width, (expected.y + 0.5) / kImg.height});
    ASSERT_TRUE(r);
    EXPECT_LT(angle_deg(r->dir, p), 1e-9)
        << "ray of pixel " << str(expected) << " dir " << str(r->dir);
  }
}

}  // namespace anamorph
