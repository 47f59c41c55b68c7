// Map projections: equirectangular, cylindrical, mercator, lambert_equal_area, stereographic and
// panini, against their defining properties.
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
double lon_of(const Vec3& d) { return degrees(std::atan2(d.x, -d.z)); }
double lat_of(const Vec3& d) { return degrees(std::asin(std::clamp(d.y, -1.0, 1.0))); }
}  // namespace

TEST(Equirectangular, PixelCentersGiveExactLongitudeAndLatitude) {
  // One degree per pixel: pixel (i, j) is centered at lon -180 + i + 1/2, lat 90 - j - 1/2.
  const VirtualCamera cam = camera("equirectangular", "", {360, 180});
  for (int j = 0; j < 180; j += 7)
    for (int i = 0; i < 360; i += 11) {
      const auto r = ray(cam, {(i + 0.5) / 360, (j + 0.5) / 180});
      ASSERT_TRUE(r);
      EXPECT_NEAR(lon_of(r->dir), -180 + i + 0.5, 1e-12) << "pixel " << i << ", " << j;
      EXPECT_NEAR(lat_of(r->dir), 90 - j - 0.5, 1e-11) << "pixel " << i << ", " << j;
    }
  // Ranges: [-100, 80] x [-30, 60] over 180 x 90 pixels, again one degree per pixel.
  const VirtualCamera part = camera(
      "equirectangular", "longitude_range = [-100, 80]\nlatitude_range = [-30, 60]", {180, 90});
  for (int j = 0; j < 90; j += 9)
    for (int i = 0; i < 180; i += 13) {
      const auto r = ray(part, {(i + 0.5) / 180, (j + 0.5) / 90});
      ASSERT_TRUE(r);
      EXPECT_NEAR(lon_of(r->dir), -100 + i + 0.5, 1e-12);
      EXPECT_NEAR(lat_of(r->dir), 60 - j - 0.5, 1e-11);
    }
}

TEST(Equirectangular, SeamPointsProjectToBothEdges) {
  const VirtualCamera cam = camera("equirectangular", "", {360, 180});
  const auto sols = cam.project(Vec3{0, 0.2, 3});  // straight behind: lon = +-180
  ASSERT_EQ(sols.size(), 2u) << str(sols);
  EXPECT_NEAR(std::min(sols[0].x, sols[1].x), 0, 1e-12);
  EXPECT_NEAR(std::max(sols[0].x, sols[1].x), 1, 1e-12);
}

TEST(Cylindrical, CentralIsLinearInTanLatitude) {
  const VirtualCamera cam = camera("cylindrical", "latitude_range = [-45, 60]", {1000, 500});
  const double top = std::tan(radians(60)), bottom = std::tan(radians(-45));
  for (double v : {0.0, 0.2, 0.5, 0.77, 1.0}) {
    const auto r = ray(cam, {0.3, v});
    ASSERT_TRUE(r);
    EXPECT_NEAR(r->dir.y / std::hypot(r->dir.x, r->dir.z), top + (bottom - top) * v, 1e-12);
    EXPECT_NEAR(lon_of(r->dir), -180 + 0.3 * 360, 1e-12);
  }
}

TEST(Cylindrical, OrthographicMovesUpTheAxis) {
  const VirtualCamera cam =
      camera("cylindrical", "projection = \"orthographic\"\nheight = 4", {1000, 500});
  for (double v : {0.0, 0.25, 1.0}) {
    const auto r = ray(cam, {0.6, v});
    ASSERT_TRUE(r);
    EXPECT_NEAR(r->org.y, 2 - 4 * v, 1e-12);
    EXPECT_NEAR(r->org.x, 0, 1e-12);
    EXPECT_NEAR(r->dir.y, 0, 1e-12) << "horizontal rays";
    EXPECT_NEAR(lon_of(r->dir), -180 + 0.6 * 360, 1e-12);
  }
  EXPECT_THROW(make_preset("cylindrical", "height = 2", {64, 64}), ParamError)
      << "height belongs to the orthographic projection";
}

TEST(Mercator, ConformalWithSquarePixels) {
  const ImageInfo img{2000, 1500};
  const VirtualCamera cam = camera("mercator", "", img);
  Rng rng(1, 2);
  for (int k = 0; k < 50; ++k) {
    const Vec2 uv{rng.uniform(), rng.uniform()};
    const auto r = ray(cam, uv);
    ASSERT_TRUE(r);
    // One pixel step right and one down turn the view by equal, perpendicular angles.
    const Vec3 du = r->ddir_du / img.width, dv = r->ddir_dv / img.height;
    EXPECT_NEAR(length(du) / length(dv), 1, 1e-12) << "uv " << str(uv);
    EXPECT_NEAR(dot(du, dv) / (length(du) * length(dv)), 0, 1e-12) << "uv " << str(uv);
  }
  // And the latitude follows y = ln tan(pi/4 + lat/2) with y linear in v.
  const VirtualCamera ranged = camera("mercator", "latitude_range = [-70, 80]", img);
  const auto y = [](double lat) { return std::log(std::tan(kPi / 4 + radians(lat) / 2)); };
  for (double v : {0.0, 0.3, 0.9}) {
    const auto r = ray(ranged, {0.5, v});
    EXPECT_NEAR(y(lat_of(r->dir)), y(80) + (y(-70) - y(80)) * v, 1e-10) << v;
  }
}

TEST(LambertEqualArea, EveryPixelCoversTheSameSolidAngle) {
  const ImageInfo img{1800, 900};
  const VirtualCamera cam = camera("lambert_equal_area", "", img);
  const auto r0 = ray(cam, {0.5, 0.5});
  const double a0 = length(cross(r0->ddir_du, r0->ddir_dv));
  EXPECT_NEAR(a0 / (img.width * img.height), 4 * kPi / (img.width * img.height), 1e-12);
  Rng rng(4, 2);
  for (int k = 0; k < 50; ++k) {
    const Vec2 uv{rng.uniform(), 0.01 + 0.98 * rng.uniform()};
    const auto r = ray(cam, uv);
    ASSERT_TRUE(r);
    EXPECT_NEAR(length(cross(r->ddir_du, r->ddir_dv)) / a0, 1, 1e-9) << "uv " << str(uv);
  }
}

TEST(Stereographic, EdgesAtHalfFovAndConformal) {
  const ImageInfo img{1600, 900};
  const VirtualCamera cam = camera("stereographic", "fov = 240", img);
  EXPECT_NEAR(angle_deg(ray(cam, {0, 0.5})->dir, {0, 0, -1}), 120, 1e-9);
  EXPECT_NEAR(angle_deg(ray(cam, {1, 0.5})->dir, {0, 0, -1}), 120, 1e-9);
  Rng rng(9, 1);
  for (int k = 0; k < 50; ++k) {
    const Vec2 uv{rng.uniform(), rng.uniform()};
    const auto r = ray(cam, uv);
    const Vec3 du = r->ddir_du / img.width, dv = r->ddir_dv / img.height;
    EXPECT_NEAR(length(du) / length(dv), 1, 1e-12) << "uv " << str(uv);
    EXPECT_NEAR(dot(du, dv) / (length(du) * length(dv)), 0, 1e-12) << "uv " << str(uv);
  }
  // Image radius is 2 tan(theta / 2) in plane units: half way out, tan(theta/2) = tan(fov/4)/2.
  const auto half = ray(cam, {0.75, 0.5});
  EXPECT_NEAR(radians(angle_deg(half->dir, {0, 0, -1})), 2 * std::atan(std::tan(radians(60)) / 2),
              1e-12);
}

TEST(Panini, ZeroCompressionIsPerspective) {
  const ImageInfo img{1280, 720};
  const VirtualCamera pan = camera("panini", "fov = 90\ncompression = 0", img);
  const VirtualCamera per = camera("perspective", "fov = 90", img);
  for (Vec2 uv : {Vec2{0, 0}, Vec2{0.3, 0.8}, Vec2{1, 0.5}, Vec2{0.9, 0.1}})
    EXPECT_LT(angle_deg(ray(pan, uv)->dir, ray(per, uv)->dir), 1e-12) << str(uv);
}

TEST(Panini, VerticalsStayVerticalAndEdgesAtHalfFov) {
  for (double d : {0.5, 1.0, 2.0}) {
    const VirtualCamera cam =
        camera("panini", "fov = 150\ncompression = " + std::to_string(d), {1920, 1080});
    for (double u : {0.0, 0.1, 0.45, 0.8}) {
      const double lon = lon_of(ray(cam, {u, 0.5})->dir);
      for (double v : {0.0, 0.3, 1.0})
        EXPECT_NEAR(lon_of(ray(cam, {u, v})->dir), lon, 1e-11) << "d " << d << " u " << u;
    }
    EXPECT_NEAR(lon_of(ray(cam, {0, 0.5})->dir), -75, 1e-10) << d;
    EXPECT_NEAR(lon_of(ray(cam, {1, 0.5})->dir), 75, 1e-10) << d;
    // Panini's definition: x = S sin(lon), y = S tan(lat), S = (d+1)/(d+cos(lon)); x, y linear
    // in the image.
    const auto r = ray(cam, {0.8, 0.2});
    const double lon = radians(lon_of(r->dir)), lat = radians(lat_of(r->dir));
    const double S = (d + 1) / (d + std::cos(lon));
    const double xe = (d + 1) * std::sin(radians(75)) / (d + std::cos(radians(75)));
    EXPECT_NEAR(S * std::sin(lon), 0.6 * xe, 1e-12) << d;
    EXPECT_NEAR(S * std::tan(lat), 0.6 * xe / (1920.0 / 1080), 1e-12) << d;
  }
  EXPECT_THROW(make_preset("panini", "fov = 250\ncompression = 0.5", {64, 64}), ParamError);
}

}  // namespace anamorph
