// Direction functions: analytic properties of each, derivatives against finite differences of
// the composed camera, and the paper's perspective and sphere-function facts.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "camera/functions.h"
#include "camera/virtual_camera.h"
#include "function_test_util.h"

namespace anamorph {
namespace {

using test::cat;
using test::expect_close;
using test::sample;
using test::str;

DirSample dir_at(const OrgFunction& org, const DirFunction& dir, Vec2 uv) {
  const SurfaceSample s = sample(org, uv);
  DirSample d;
  EXPECT_TRUE(dir.eval(uv, s, &d)) << "no direction at (" << uv.x << ", " << uv.y << ")";
  return d;
}

double angle_between(const Vec3& a, const Vec3& b) {
  return std::atan2(length(cross(a, b)), dot(a, b));
}

struct Pair {
  const char* name;
  const char* org_type;
  std::string org;
  const char* dir_type;
  std::string dir;
  double tol = 1e-6;
};

void PrintTo(const Pair& p, std::ostream* os) { *os << p.name; }

std::vector<Pair> pairs() {
  const std::string sphere =
      "center = [0, 0, -4]\nradius = 1.5\nu_range = [-150, 120]\n"
      "v_range = [75, -80]";
  const std::string bspline =
      "points = [[[0, 0, 0], [1, 0.2, 0.1], [2, 0, 0.5], [3, 0.1, 0]], "
      "[[0, -1, 0.3], [1, -1, 1], [2, -1.2, 0.2], [3, -1, 0.4]], "
      "[[0.2, -2, 0], [1, -2, 0.5], [2, -2.1, 1], [3, -2, 0]]]\ndegree_u = 3\ndegree_v = 2";
  return {
      {"constant", "sphere", sphere, "constant", "direction = [1, 2, -3]"},
      {"from_surface_sphere", "point", "", "from_surface",
       "surface = { type = \"sphere\", center = [0.5, 0, -3], radius = 1 }"},
      {"from_surface_cylinder", "plane", "", "from_surface",
       "surface = { type = \"cylinder\", radius = 2, v_range = [1, -1] }\ncenter = [0, 0.5, 0]"},
      {"toward", "sphere", sphere, "toward", "point = [1, 2, 3]"},
      {"away_from", "bspline", bspline, "away_from", "point = [1, -1, -5]"},
      {"normal_sphere", "sphere", sphere, "normal", ""},
      {"normal_flipped", "bspline", bspline, "normal", "flip = true"},
      {"tangent_u", "torus", "major_radius = 2\nminor_radius = 0.5\nv_range = [160, -170]",
       "tangent_u", ""},
      {"tangent_v", "bspline", bspline, "tangent_v", "flip = true"},
      {"deviated_sphere", "sphere", sphere, "deviated_normal", "angle = 30\nazimuth = 70"},
      {"deviated_bspline", "bspline", bspline, "deviated_normal",
       "angle = 50\nazimuth = -120\nflip = true"},
      {"deviated_superquadric", "superquadric",
       "radii = [1, 2, 0.5]\nexponent_ns = 1.5\nexponent_ew = 1.2\nu_range = [-150, 120]\n"
       "v_range = [75, -80]",
       "deviated_normal", "angle = 170\nazimuth = 10"},
      {"expression", "sphere", sphere, "expression",
       "x = \"nx + k * u * oy\"\ny = \"ny - v * ox\"\nz = \"nz + sin(u * v) + oz\"\n"
       "constants = { k = 0.7 }\nu_range = [-1, 2]",
       2e-5},
      {"scattered", "point", "", "scattered",
       "points = [[0.1, 0.1, -1, 1, -1], [0.9, 0.15, 1, 1, -1.5], [0.5, 0.5, 0, 0, -1], "
       "[0.2, 0.85, -1, -1, -1], [0.8, 0.9, 1, -0.8, -1]]\nkernel = \"multiquadric\""},
      {"table", "point", "", "table",
       "samples = [[[-1, 0.8, -1], [0, 1, -1.2], [1, 0.9, -1]], [[-1.1, 0, -1], [0, 0, -1], "
       "[1, 0.1, -0.9]], [[-0.9, -1, -1], [0, -1.1, -1.1], [1, -1, -1]], [[-1, -2, -1], "
       "[0.1, -2, -1], [1, -2.1, -1.2]]]"},
      {"scattered_sphere_fisheye", "point", "", "scattered_sphere",
       "points = [[0.3, 0.3, 0, 0.2, -1], [0.7, 0.6, 1, 0, 0.1], [0.6, 0.2, 0, 1, 0]]\n"
       "fov = 200\nshape = 2"},
      {"scattered_sphere_equirect", "point", "", "scattered_sphere",
       "points = [[0.3, 0.3, 0, 0.2, -1], [0.7, 0.6, 1, 0, 0.1], [0.6, 0.2, 0, 1, 0], "
       "[0.1, 0.9, 0, -1, 0]]\nlayout = \"equirectangular\"\nkernel = \"thin_plate\"\n"
       "u_range = [-150, 170]"},
  };
}

class DirFunctionTest : public ::testing::TestWithParam<Pair> {};

TEST_P(DirFunctionTest, DerivativesMatchFiniteDifferences) {
  const Pair& c = GetParam();
  const auto org = make_org(c.org_type, c.org);
  const auto dir = make_dir(c.dir_type, c.dir);
  const double h = 1e-5;
  for (const Vec2 uv : {Vec2{0.3, 0.35}, Vec2{0.62, 0.7}, Vec2{0.83, 0.22}, Vec2{0.47, 0.56}}) {
    const DirSample d = dir_at(*org, *dir, uv);
    const Vec3 fu =
        (dir_at(*org, *dir, {uv.x + h, uv.y}).d - dir_at(*org, *dir, {uv.x - h, uv.y}).d) / (2 * h);
    const Vec3 fv =
        (dir_at(*org, *dir, {uv.x, uv.y + h}).d - dir_at(*org, *dir, {uv.x, uv.y - h}).d) / (2 * h);
    expect_close(d.dd_du, fu, c.tol, cat("dd_du at (", uv.x, ", ", uv.y, ")"));
    expect_close(d.dd_dv, fv, c.tol, cat("dd_dv at (", uv.x, ", ", uv.y, ")"));
  }
}

TEST_P(DirFunctionTest, CameraDifferentialsMatchNeighbouringRays) {
  // Through the lead's VirtualCamera: the unit-direction differentials it derives from ours.
  const Pair& c = GetParam();
  VirtualCameraParts parts;
  parts.org = make_org(c.org_type, c.org);
  parts.dir = make_dir(c.dir_type, c.dir);
  const VirtualCamera cam(std::move(parts));
  const double h = 1e-6;
  const Vec2 uv{0.41, 0.63};
  const auto r = cam.generate_pinhole(uv), ru = cam.generate_pinhole({uv.x + h, uv.y}),
             rl = cam.generate_pinhole({uv.x - h, uv.y});
  ASSERT_TRUE(r && ru && rl);
  expect_close(r->ddir_du, (ru->dir - rl->dir) / (2 * h), 20 * c.tol, "ddir_du");
  expect_close(r->dorg_du, (ru->org - rl->org) / (2 * h), 1e-6, "dorg_du");
}

INSTANTIATE_TEST_SUITE_P(All, DirFunctionTest, ::testing::ValuesIn(pairs()),
                         [](const auto& p) { return std::string(p.param.name); });

TEST(DirFunctionTest, EveryRegisteredFunctionIsCovered) {
  const auto all = pairs();
  for (const auto& f : dir_functions()) {
    bool found = false;
    for (const auto& c : all) found |= f.name == c.dir_type;
    EXPECT_TRUE(found) << "direction function '" << f.name << "' has no case in dir_function_test";
  }
}

TEST(NormalDir, OnAPlaneIsConstant) {
  const auto org =
      make_org("plane", "center = [1, 2, 3]\nedge_u = [2, 0, 1]\nedge_v = [0, -1, 0.5]");
  const auto dir = make_dir("normal");
  const Vec3 expected = normalize(cross(Vec3{2, 0, 1}, Vec3{0, -1, 0.5}));
  for (int j = 0; j <= 8; ++j)
    for (int i = 0; i <= 8; ++i) {
      const DirSample d = dir_at(*org, *dir, {i / 8.0, j / 8.0});
      expect_close(d.d, expected, 1e-15, "normal direction");
      expect_close(d.dd_du, {}, 0, "dd_du");
      expect_close(d.dd_dv, {}, 0, "dd_dv");
    }
}

TEST(NormalDir, OrgPointHasNoRay) {
  VirtualCameraParts parts;
  parts.org = make_org("point");
  parts.dir = make_dir("normal");
  const VirtualCamera cam(std::move(parts));
  EXPECT_FALSE(cam.generate_pinhole({0.5, 0.5})) << "a point has no normal: no ray, not NaN";
}

TEST(DeviatedNormalDir, AngleToTheNormalIsExact) {
  const auto org = make_org("torus", "major_radius = 2\nminor_radius = 0.7\naxis = [0, 1, 1]");
  for (const double angle : {0.0, 10.0, 45.0, 90.0, 135.0, 180.0}) {
    for (const double azimuth : {0.0, 90.0, 200.0}) {
      const auto dir = make_dir("deviated_normal", cat("angle = ", angle, "\nazimuth = ", azimuth));
      for (int j = 1; j < 10; ++j)
        for (int i = 1; i < 10; ++i) {
          const Vec2 uv{i / 10.0, j / 10.0 + 0.013};
          const SurfaceSample s = sample(*org, uv);
          const DirSample d = dir_at(*org, *dir, uv);
          EXPECT_NEAR(degrees(angle_between(d.d, s.n)), angle, 1e-10)
              << "azimuth " << azimuth << " at " << uv.x << ", " << uv.y;
        }
    }
  }
}

TEST(DeviatedNormalDir, AzimuthTurnsCounterclockwiseInTheImage) {
  // A plane facing -z seen by the default camera: u right = +x, v down = -y.
  const auto org = make_org("plane");
  const auto at = [&](double az) {
    return dir_at(*org, *make_dir("deviated_normal", cat("angle = 30\nazimuth = ", az)), {0.5, 0.5})
        .d;
  };
  const double s = std::sin(radians(30)), c = std::cos(radians(30));
  expect_close(at(0), {s, 0, -c}, 1e-15, "azimuth 0 tilts toward image right");
  expect_close(at(90), {0, s, -c}, 1e-15, "azimuth 90 tilts toward image up");
  expect_close(at(180), {-s, 0, -c}, 1e-15, "azimuth 180 tilts left");
}

TEST(TowardDir, RaysPassThroughThePoint) {
  const Vec3 target{1, 2, 3};
  VirtualCameraParts parts;
  parts.org = make_org("sphere", "center = [0, 0, 0]\nradius = 5");
  parts.dir = make_dir("toward", "point = [1, 2, 3]");
  const VirtualCamera cam(std::move(parts));
  for (int j = 0; j <= 10; ++j)
    for (int i = 0; i <= 10; ++i) {
      const auto r = cam.generate_pinhole({i / 10.0, j / 10.0});
      ASSERT_TRUE(r);
      const Vec3 to = target - r->org;
      EXPECT_NEAR(length(cross(to, r->dir)), 0, 1e-12)
          << "ray " << str(r->org) << " + t " << str(r->dir) << " misses the point";
      EXPECT_GT(dot(to, r->dir), 0) << "the point lies ahead";
    }
}

TEST(AwayFromDir, RaysLeaveThePoint) {
  const auto org = make_org("cylinder", "radius = 2");
  const auto dir = make_dir("away_from", "point = [0, 0.5, 0]");
  for (int i = 0; i <= 10; ++i) {
    const Vec2 uv{i / 10.0, 0.3};
    const Vec3 p = sample(*org, uv).p;
    expect_close(normalize(dir_at(*org, *dir, uv).d), normalize(p - Vec3{0, 0.5, 0}), 1e-15,
                 "direction");
  }
}

TEST(FromSurfaceDir, PointWithPlaneIsTheTextbookPinhole) {
  // org = point, dir = from_surface plane at distance 1 spanning the field of view.
  const double fov = 63, aspect = 16.0 / 9.0;
  const double tx = std::tan(radians(fov) / 2), ty = tx / aspect;
  VirtualCameraParts parts;
  parts.org = make_org("point", "position = [0, 0, 0]");
  parts.dir =
      make_dir("from_surface", cat("surface = { type = \"plane\", center = [0, 0, -1], edge_u = [",
                                   2 * tx, ", 0, 0], edge_v = [0, ", -2 * ty, ", 0] }"));
  const VirtualCamera cam(std::move(parts));
  double worst = 0;
  for (int j = 0; j < 90; ++j)
    for (int i = 0; i < 160; ++i) {
      const double u = (i + 0.5) / 160, v = (j + 0.5) / 90;
      const Vec3 pinhole = normalize(Vec3{(2 * u - 1) * tx, (1 - 2 * v) * ty, -1});
      const auto r = cam.generate_pinhole({u, v});
      ASSERT_TRUE(r);
      worst = std::max(worst, angle_between(r->dir, pinhole));
      ASSERT_EQ(length(r->org), 0);
    }
  EXPECT_LT(worst, 1e-6) << "largest angle to the textbook pinhole ray (rad): " << worst;
  EXPECT_LT(worst, 1e-14) << "in fact it is the same arithmetic up to rounding: " << worst;
}

TEST(FromSurfaceDir, SphereNotEnclosingTheCenterMirrorsAndZooms) {
  // The paper: a sphere not enclosing the coordinate center gives each direction of the cone it
  // subtends twice (both intersections of a line through the center with the sphere), with the
  // mirroring circle where that line is tangent; moving the sphere away narrows the cone.
  const auto org = make_org("point");
  for (const double dist : {3.0, 6.0}) {
    const Vec3 c{0, 0, -dist};
    const double r = 1;
    const auto dir = make_dir("from_surface", cat("surface = { type = \"sphere\", center = [0, 0, ",
                                                  -dist, "], radius = 1 }"));
    // Every direction lies within the cone of half-angle asin(r / dist) around the center.
    double widest = 0;
    for (int j = 0; j <= 30; ++j)
      for (int i = 0; i <= 30; ++i)
        widest = std::max(widest, angle_between(dir_at(*org, *dir, {i / 30.0, j / 30.0}).d, c));
    EXPECT_LE(widest, std::asin(r / dist) + 1e-12) << "distance " << dist;
    EXPECT_GE(widest, std::asin(r / dist) * 0.95) << "the sphere spans (nearly) the whole cone";

    // A sampled point and the other intersection of its line of sight with the sphere (the
    // product of the two distances along the line is |c|^2 - r^2).
    const Vec2 uv1{0.45, 0.4};
    const Vec3 s1 = sample(*make_org("sphere", cat("center = [0, 0, ", -dist, "]")), uv1).p;
    const DirSample e1 = dir_at(*org, *dir, uv1);
    expect_close(e1.d, s1, 1e-12, "dir = S - center");
    const Vec3 d1 = normalize(e1.d);
    const Vec3 p2 = d1 * ((dist * dist - r * r) / length(s1));
    ASSERT_GT(length(p2 - s1), 0.1) << "not on the mirroring circle itself";
    // (u, v) of p2 from the documented parameterization (longitude from -z toward +x).
    const Vec3 q = (p2 - c) / r;
    const double lon = degrees(std::atan2(q.x, -q.z)), lat = degrees(std::asin(q.y));
    const Vec2 uv2{(lon + 180) / 360, (90 - lat) / 180};
    EXPECT_GT(length(uv2 - uv1), 0.05) << "two different image positions";
    const DirSample e2 = dir_at(*org, *dir, uv2);
    EXPECT_LT(angle_between(d1, e2.d), 1e-12)
        << "uv " << uv1.x << "," << uv1.y << " and " << uv2.x << "," << uv2.y
        << " should see the same direction: " << str(d1) << " vs " << str(e2.d);
    // The two copies are mirror images: the direction map's orientation differs in sign.
    const double o1 = dot(cross(e1.dd_du, e1.dd_dv), e1.d),
                 o2 = dot(cross(e2.dd_du, e2.dd_dv), e2.d);
    EXPECT_LT(o1 * o2, 0) << "orientations " << o1 << " and " << o2;
  }
}

}  // namespace
}  // namespace anamorph
