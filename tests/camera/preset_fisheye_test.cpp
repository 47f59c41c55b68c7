// fisheye, mirror_ball and dome: analytic angles of the radial mappings, the image circle,
// orientation, and strict parameters.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

#include "preset_test_util.h"

namespace anamorph {

using test::angle_deg;
using test::camera;
using test::ray;
using test::str;

namespace {

// Identity rig: camera space = world, looking along -z.
constexpr Vec3 kForward{0, 0, -1};

struct MappingCase {
  const char* mapping;
  double fov;
  const char* extra;
};

// theta(r) from the published definitions, written out independently of the implementation.
double expected_theta(const MappingCase& m, double r) {
  const double tm = radians(m.fov) / 2;
  const std::string name = m.mapping;
  if (name == "equidistant") return r * tm;
  if (name == "equisolid") return 2 * std::asin(r * std::sin(tm / 2));
  if (name == "stereographic") return 2 * std::atan(r * std::tan(tm / 2));
  if (name == "orthographic") return std::asin(r * std::sin(tm));
  // polynomial [0, 1.2, 0, -0.1, 0.05]
  return 1.2 * r - 0.1 * r * r * r + 0.05 * r * r * r * r;
}

const MappingCase kMappings[] = {
    {"equidistant", 90, ""},    {"equidistant", 180, ""},
    {"equidistant", 360, ""},   {"equisolid", 180, ""},
    {"equisolid", 360, ""},     {"stereographic", 120, ""},
    {"stereographic", 300, ""}, {"orthographic", 180, ""},
    {"orthographic", 100, ""},  {"polynomial", degrees(2.3), "poly = [0, 1.2, 0, -0.1, 0.05]\n"},
};

std::string fisheye_toml(const MappingCase& m, const std::string& fit) {
  char fov[64];
  std::snprintf(fov, sizeof fov, "%.17g", m.fov);
  return std::string("fov = ") + fov + "\nmapping = \"" + m.mapping + "\"\n" + m.extra + fit;
}

}  // namespace

TEST(Fisheye, EdgeOfTheCircleIsHalfTheFovForEveryMapping) {
  for (const MappingCase& m : kMappings) {
    // circle fit on a landscape image: the circle touches the top and bottom edges; its left and
    // right ends lie at u = 1/2 -+ (H/2)/W.
    const ImageInfo img{1600, 1000};
    const VirtualCamera cam = camera("fisheye", fisheye_toml(m, ""), img);
    const double du = 0.5 * img.height / img.width;
    for (Vec2 uv : {Vec2{0.5, 0}, Vec2{0.5, 1}, Vec2{0.5 - du, 0.5}, Vec2{0.5 + du, 0.5}}) {
      const auto r = ray(cam, uv);
      ASSERT_TRUE(r) << m.mapping << " " << m.fov << " uv " << str(uv);
      EXPECT_NEAR(angle_deg(r->dir, kForward), m.fov / 2, 1e-9)
          << m.mapping << " fov " << m.fov << " uv " << str(uv) << " dir " << str(r->dir);
    }
    // full_frame: the corners lie on the circle.
    const VirtualCamera full = camera("fisheye", fisheye_toml(m, "fit = \"full_frame\""), img);
    for (Vec2 uv : {Vec2{0, 0}, Vec2{1, 1}}) {
      const auto r = ray(full, uv);
      ASSERT_TRUE(r) << m.mapping << " full_frame corner";
      EXPECT_NEAR(angle_deg(r->dir, kForward), m.fov / 2, 1e-7) << m.mapping << " full_frame";
    }
    // pixels: a 500-pixel circle ends 250 pixels right of the center.
    const VirtualCamera px =
        camera("fisheye", fisheye_toml(m, "fit = \"pixels\"\ncircle_diameter = 500"), img);
    const auto r = ray(px, {0.5 + 250.0 / img.width, 0.5});
    ASSERT_TRUE(r);
    EXPECT_NEAR(angle_deg(r->dir, kForward), m.fov / 2, 1e-9) << m.mapping << " pixels";
  }
}

TEST(Fisheye, AngleFollowsTheMappingInside) {
  for (const MappingCase& m : kMappings) {
    const ImageInfo img{1000, 1000};
    const VirtualCamera cam = camera("fisheye", fisheye_toml(m, ""), img);
    for (double rr : {0.1, 0.37, 0.5, 0.83}) {
      // Straight up from the center: image radius rr, azimuth +y.
      const auto r = ray(cam, {0.5, 0.5 - rr / 2});
      ASSERT_TRUE(r);
      EXPECT_NEAR(angle_deg(r->dir, kForward), degrees(expected_theta(m, rr)), 1e-9)
          << m.mapping << " fov " << m.fov << " r " << rr;
      EXPECT_NEAR(r->dir.x, 0, 1e-12) << "azimuth straight up";
      if (angle_deg(r->dir, kForward) > 1e-6) {
        EXPECT_GT(r->dir.y, 0) << "up in the image is +y";
      }
    }
  }
}

TEST(Fisheye, OutsideTheCircleThereIsNoRay) {
  const VirtualCamera cam = camera("fisheye", "fov = 180", {1920, 1080});
  for (Vec2 uv : {Vec2{0, 0}, Vec2{1, 1}, Vec2{0.05, 0.5}, Vec2{0.5 + 541.0 / 1920, 0.5}}) {
    const auto r = ray(cam, uv);
    EXPECT_FALSE(r) << "uv " << str(uv) << " gave dir " << (r ? str(r->dir) : "");
  }
  // Just inside the rim there is one.
  EXPECT_TRUE(ray(cam, {0.5 + 539.0 / 1920, 0.5}));
  // And points beyond fov/2 are not projected.
  EXPECT_TRUE(cam.project(Vec3{0, 0, 1}).empty()) << "behind a 180-degree fisheye";
  EXPECT_EQ(cam.project(Vec3{1, 0, -1e-3}).size(), 1u) << "just in front of the rim";
}

TEST(Fisheye, AnnularPolynomialHasNoDirectionAtTheCenter) {
  // theta(0) = k0 > 0: the center pixel is a whole cone of directions, so it gets no ray (never
  // a NaN); its neighbours look k0 off the axis.
  const VirtualCamera cam =
      camera("fisheye", "fov = 180\nmapping = \"polynomial\"\npoly = [0.2, 1.3707963267948966]",
             {101, 101});
  EXPECT_FALSE(ray(cam, {0.5, 0.5}));
  const auto r = ray(cam, {0.5 + 1e-9, 0.5});
  ASSERT_TRUE(r);
  EXPECT_NEAR(angle_deg(r->dir, kForward), degrees(0.2), 1e-6);
}

TEST(Fisheye, StrictParameters) {
  const auto key_of = [](const std::string& toml) -> std::string {
    try {
      make_preset("fisheye", toml, {100, 100});
    } catch (const ParamError& e) {
      return e.key;
    }
    return "<accepted>";
  };
  EXPECT_EQ(key_of("fov = 400"), "fov");
  EXPECT_EQ(key_of("fov = 200\nmapping = \"orthographic\""), "fov");
  EXPECT_EQ(key_of("fov = 360\nmapping = \"stereographic\""), "fov");
  EXPECT_EQ(key_of("mapping = \"polynomial\""), "mapping");
  EXPECT_EQ(key_of("poly = [0, 1]"), "poly");
  EXPECT_EQ(key_of("fov = 120\nmapping = \"polynomial\"\npoly = [0, 1.5707963267948966]"), "fov");
  EXPECT_EQ(key_of("fov = 180\nmapping = \"polynomial\"\npoly = [0, 4, -2.4292036732051034]"),
            "poly")
      << "theta(r) decreasing near r = 1 must be rejected";
  EXPECT_EQ(key_of("fit = \"pixels\""), "fit");
  EXPECT_EQ(key_of("circle_diameter = 50"), "circle_diameter");
  EXPECT_EQ(key_of("mapping = \"equirectangular\""), "mapping");
  EXPECT_EQ(key_of("fov = 180\nmapping = \"polynomial\"\npoly = [0, 1.5707963267948966]"),
            "<accepted>");
}

TEST(Fisheye, PolynomialOfHighDegree) {
  // theta(r) = sum k_i r^i with terms up to r^11 (odd, as a Kannala-Brandt lens has them), the
  // last coefficient chosen so that theta(1) = 100 degrees.
  double k[12] = {0, 1.5, 0, 0.08, 0, -0.05, 0, 0.02, 0, -0.01, 0, 0};
  double sum = 0;
  for (double c : k) sum += c;
  k[11] = radians(100) - sum;
  std::string poly = "poly = [";
  for (int i = 0; i < 12; ++i) {
    char c[40];
    std::snprintf(c, sizeof c, "%s%.17g", i ? ", " : "", k[i]);
    poly += c;
  }
  const VirtualCamera cam =
      camera("fisheye", "fov = 200\nmapping = \"polynomial\"\n" + poly + "]", {1000, 1000});
  for (double rr : {0.05, 0.3, 0.61, 0.9, 0.999}) {
    double theta = 0;
    for (int i = 11; i >= 0; --i) theta = theta * rr + k[i];
    const auto r = ray(cam, {0.5 + rr / 2, 0.5});
    ASSERT_TRUE(r) << "r " << rr;
    EXPECT_NEAR(angle_deg(r->dir, kForward), degrees(theta), 1e-9) << "r " << rr;
    // And back: the inverse map solves theta(r) for r.
    const auto uv = cam.project(r->org + r->dir * 5);
    ASSERT_EQ(uv.size(), 1u) << "r " << rr;
    EXPECT_NEAR(uv[0].x, 0.5 + rr / 2, 1e-9) << "r " << rr;
  }
  // 24 coefficients (degree 23) are accepted, 25 are not.
  std::string p24 = "[0, 1.5707963267948966", p25;
  for (int i = 2; i < 24; ++i) p24 += ", 0";
  p25 = p24 + ", 0]";
  p24 += "]";
  EXPECT_NO_THROW(make_preset("fisheye", "mapping = \"polynomial\"\npoly = " + p24, {64, 64}));
  try {
    make_preset("fisheye", "mapping = \"polynomial\"\npoly = " + p25, {64, 64});
    ADD_FAILURE() << "25 coefficients accepted";
  } catch (const ParamError& e) {
    EXPECT_EQ(e.key, "poly");
    EXPECT_NE(std::string(e.what()).find("1 to 24 coefficients (degree up to 23), not 25"),
              std::string::npos)
        << e.what();
  }
}

TEST(Fisheye, MaxAngleCutsACircleInsideTheImageCircle) {
  const VirtualCamera cam = camera("fisheye", "fov = 180\nmax_angle = 60", {900, 900});
  int kept = 0, cut = 0;
  for (int j = 0; j < 90; ++j)
    for (int i = 0; i < 90; ++i) {
      const Vec2 uv{(i + 0.5) / 90, (j + 0.5) / 90};
      const double theta = 90 * std::hypot(2 * uv.x - 1, 2 * uv.y - 1);  // equidistant
      if (theta > 90) continue;
      const auto r = ray(cam, uv);
      EXPECT_EQ(bool(r), theta <= 60) << "uv " << str(uv) << " theta " << theta;
      (r ? kept : cut)++;
    }
  EXPECT_GT(kept, 100);
  EXPECT_GT(cut, 100);
  // The inverse map agrees: 50 degrees off the axis is seen, 70 is not.
  EXPECT_EQ(cam.project({std::sin(radians(50)), 0, -std::cos(radians(50))}).size(), 1u);
  EXPECT_TRUE(cam.project({std::sin(radians(70)), 0, -std::cos(radians(70))}).empty());
}

TEST(Fisheye, MinElevationCutsBelowTheWorldHorizon) {
  // A fisheye looking at the horizon, tilted 20 degrees up: nothing below 5 degrees under the
  // horizon has a ray, whatever the tilt, and the inverse map agrees.
  const std::string keys =
      "fov = 180\nlook_from = [1, 2, 3]\nlook_at = [1, 2.36397, 2]\nmin_elevation = -5";
  const VirtualCamera cam = camera("fisheye", keys, {400, 400});
  const VirtualCamera all = camera("fisheye",
                                   "fov = 180\nlook_from = [1, 2, 3]\n"
                                   "look_at = [1, 2.36397, 2]",
                                   {400, 400});
  const double s5 = std::sin(radians(-5));
  int cut = 0;
  for (int j = 0; j < 40; ++j)
    for (int i = 0; i < 40; ++i) {
      const Vec2 uv{(i + 0.5) / 40, (j + 0.5) / 40};
      const auto a = ray(all, uv);
      if (!a) continue;
      const auto r = ray(cam, uv);
      const double elevation = a->dir.y / length(a->dir);
      EXPECT_EQ(bool(r), elevation >= s5) << "uv " << str(uv) << " dir " << str(a->dir);
      if (!r) ++cut;
      const auto back = cam.project(a->org + a->dir * 4);
      EXPECT_EQ(back.empty(), elevation < s5) << "uv " << str(uv);
    }
  EXPECT_GT(cut, 100) << "the bottom of the circle lies below -5 degrees";
}

// POV-Ray's omnimax camera (tracepixel.cpp, "case OMNIMAX_CAMERA"), written out from its
// formula at image position (u, v) of a W x H frame: x0 = 2u - 1, y0 = 1 - 2v, the frame's
// aspect correction, rad = |(x0, y0)| (no ray beyond 1), phi = the polar angle of (x0, y0),
// theta = rad * angle / 2, and dir = cos(phi) sin(theta) right + sin(phi) sin(theta) up +
// cos(theta) direction. (POV-Ray samples row y at (H - 1 - y) / H; we compare the mapping at
// the same continuous positions.)
std::optional<Vec3> povray_omnimax(Vec2 uv, double W, double H, double angle) {
  double x0 = 2 * uv.x - 1, y0 = 1 - 2 * uv.y;
  const double aspect = W / H;
  if (aspect > 1) {
    if (aspect > 1.283458) {
      x0 *= aspect / 1.283458;
      y0 = (y0 - 1) / 1.283458 + 1;
    } else {
      y0 = (y0 - 1) / aspect + 1;
    }
  } else {
    y0 /= aspect;
  }
  const double rad = std::sqrt(x0 * x0 + y0 * y0);
  if (rad > 1) return std::nullopt;
  const double phi = rad == 0 ? 0 : (x0 < 0 ? kPi - std::asin(y0 / rad) : std::asin(y0 / rad));
  const double theta = rad * angle * kPi / 360;
  // right = +x, up = +y, direction = -z (our right-handed camera space).
  return Vec3{std::cos(phi) * std::sin(theta), std::sin(phi) * std::sin(theta), -std::cos(theta)};
}

TEST(Fisheye, OmnimaxFitIsPovRaysOmnimaxCamera) {
  for (const ImageInfo img :
       {ImageInfo{1540, 1200}, ImageInfo{1600, 900}, ImageInfo{800, 1000}, ImageInfo{700, 700}}) {
    const VirtualCamera cam = camera("fisheye", "fov = 180\nfit = \"omnimax\"", img);
    int rays = 0;
    for (int j = 0; j < 60; ++j)
      for (int i = 0; i < 60; ++i) {
        const Vec2 uv{(i + 0.5) / 60, (j + 0.5) / 60};
        const auto want = povray_omnimax(uv, img.width, img.height, 180);
        const auto got = ray(cam, uv);
        ASSERT_EQ(bool(got), bool(want)) << img.width << "x" << img.height << " uv " << str(uv);
        if (!got) continue;
        ++rays;
        EXPECT_LT(length(got->dir - *want), 1e-12)
            << img.width << "x" << img.height << " uv " << str(uv) << ": " << str(got->dir)
            << " vs POV-Ray " << str(*want);
      }
    EXPECT_GT(rays, 1000) << img.width << "x" << img.height;
  }
  try {
    make_preset("fisheye", "fit = \"omnimax\"\ncircle_center = [0.5, 0.6]", {64, 48});
    ADD_FAILURE() << "circle_center with fit = omnimax accepted";
  } catch (const ParamError& e) {
    EXPECT_EQ(e.key, "circle_center");
  }
}

TEST(MirrorBall, CenterReflectsBackRimShowsBehindTheBall) {
  // Ball at the origin, photographed along -z: the center shows +z, the rim -z, and a normal
  // tilted by 45 degrees (r = sin 45) turns the ray by 90 degrees.
  const VirtualCamera cam = camera("mirror_ball", "", {800, 800});
  const auto c = ray(cam, {0.5, 0.5});
  ASSERT_TRUE(c);
  EXPECT_LT(angle_deg(c->dir, {0, 0, 1}), 1e-9) << str(c->dir);
  const auto rim = ray(cam, {0.5, 0});
  ASSERT_TRUE(rim);
  EXPECT_LT(angle_deg(rim->dir, {0, 0, -1}), 1e-6) << str(rim->dir);
  const double r45 = std::sqrt(0.5);
  const auto right = ray(cam, {0.5 + r45 / 2, 0.5}), up = ray(cam, {0.5, 0.5 - r45 / 2});
  ASSERT_TRUE(right && up);
  EXPECT_LT(angle_deg(right->dir, {1, 0, 0}), 1e-9) << "right of the ball reflects +x";
  EXPECT_LT(angle_deg(up->dir, {0, 1, 0}), 1e-9) << "top of the ball reflects +y";
  // The mirror law itself: ray (0,0,-1) reflected about the sphere normal at image point (a, b).
  for (Vec2 ab : {Vec2{0.3, 0.2}, Vec2{-0.6, 0.5}, Vec2{0.1, -0.9}}) {
    const Vec3 n{ab.x, ab.y, std::sqrt(1 - ab.x * ab.x - ab.y * ab.y)};
    const Vec3 in{0, 0, -1};
    const Vec3 out = in - n * (2 * dot(in, n));
    const auto r = ray(cam, {0.5 + ab.x / 2, 0.5 - ab.y / 2});
    ASSERT_TRUE(r);
    EXPECT_LT(angle_deg(r->dir, out), 1e-9) << "image point " << str(ab);
  }
}

TEST(Dome, DomemasterOrientationAndTilt) {
  for (double tilt : {0.0, 20.0}) {
    const std::string toml =
        "look_from = [1, 2, 3]\nlook_at = [1, 2, -5]\ntilt = " + std::to_string(tilt);
    const VirtualCamera cam = camera("dome", toml, {1024, 1024});
    const double t = radians(tilt);
    const Vec3 up{0, 1, 0}, front{0, 0, -1}, right{1, 0, 0};
    const Vec3 zenith = up * std::cos(t) + front * std::sin(t);
    const auto c = ray(cam, {0.5, 0.5});
    ASSERT_TRUE(c);
    EXPECT_LT(angle_deg(c->dir, zenith), 1e-9) << "center = zenith, tilt " << tilt;
    // Bottom of the circle = the front spring line, top = the back, right = right.
    const auto bottom = ray(cam, {0.5, 1}), top = ray(cam, {0.5, 0}), rt = ray(cam, {1, 0.5});
    ASSERT_TRUE(bottom && top && rt);
    EXPECT_LT(angle_deg(bottom->dir, front * std::cos(t) - up * std::sin(t)), 1e-9) << tilt;
    EXPECT_LT(angle_deg(top->dir, -front * std::cos(t) + up * std::sin(t)), 1e-9) << tilt;
    EXPECT_LT(angle_deg(rt->dir, right), 1e-9) << tilt;
  }
}

TEST(Dome, OffCenterEyeLooksAtTheDomePoint) {
  // Eye below and behind the center of a tilted dome of radius 10: each ray starts at the eye and
  // passes through the dome point that the equidistant domemaster assigns to the pixel.
  const Vec3 center{1, 2, 3}, eye_offset{0.5, -2, 3};
  const double R = 10, tilt = 30;
  const VirtualCamera cam =
      camera("dome",
             "look_from = [1, 2, 3]\nlook_at = [1, 2, -5]\nradius = 10\ntilt = 30\n"
             "eye_offset = [0.5, -2, 3]",
             {1024, 1024});
  const double t = radians(tilt);
  const Vec3 A{0, std::cos(t), -std::sin(t)}, U{0, std::sin(t), std::cos(t)}, X{1, 0, 0};
  for (Vec2 uv : {Vec2{0.5, 0.5}, Vec2{0.2, 0.6}, Vec2{0.7, 0.05}, Vec2{0.93, 0.41}}) {
    const double a = 2 * uv.x - 1, b = 1 - 2 * uv.y, rho = std::hypot(a, b);
    const double theta = rho * kPi / 2;
    const Vec3 unit =
        rho > 0 ? (X * (a / rho) + U * (b / rho)) * std::sin(theta) + A * std::cos(theta) : A;
    const Vec3 dome_point = center + unit * R;
    const auto r = ray(cam, uv);
    ASSERT_TRUE(r);
    EXPECT_LT(length(r->org - (center + eye_offset)), 1e-12) << "org = the eye";
    const Vec3 to = dome_point - r->org;
    EXPECT_LT(angle_deg(r->dir, to), 1e-9)
        << "uv " << str(uv) << " dir " << str(r->dir) << " expected toward " << str(dome_point);
  }
  EXPECT_THROW(make_preset("dome", "radius = 1\neye_offset = [0, 0, 1.5]", {64, 64}), ParamError);
}

}  // namespace anamorph
