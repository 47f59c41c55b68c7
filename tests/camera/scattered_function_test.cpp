// Scattered-data functions (org `scattered`, dir `scattered` and `scattered_sphere`) and the
// radial basis interpolator under them: exact interpolation, plane reproduction, the smoothing
// limit, the layouts against the presets, and the errors users get. (Values against SciPy's
// RBFInterpolator: python/tests/test_scattered.py.)
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "camera/functions.h"
#include "camera/presets.h"
#include "camera/scattered_common.h"
#include "camera/virtual_camera.h"
#include "function_test_util.h"
#include "math/rbf.h"
#include "math/rng.h"
#include "test_util.h"

namespace anamorph {
namespace {

using test::cat;
using test::expect_close;
using test::sample;
using test::str;

struct Datum {
  double u, v;
  Vec3 p;
};

std::string rows(const std::vector<Datum>& data) {
  std::string s = "points = [";
  for (size_t i = 0; i < data.size(); ++i)
    s += cat(i ? ", [" : "[", data[i].u, ", ", data[i].v, ", ", data[i].p.x, ", ", data[i].p.y,
             ", ", data[i].p.z, "]");
  return s + "]\n";
}

std::vector<Datum> random_data(int n, uint64_t seed) {
  Rng rng(seed, 1);
  std::vector<Datum> d;
  for (int i = 0; i < n; ++i) {
    const double u = rng.uniform(), v = rng.uniform();
    d.push_back({u, v, {u + rng.uniform(), rng.uniform() - v, 2 * rng.uniform() - 1}});
  }
  return d;
}

TEST(ScatteredOrg, PassesThroughEveryPointWithEachKernel) {
  const auto data = random_data(25, 7);
  for (const char* k :
       {"thin_plate", "multiquadric", "inverse_multiquadric", "gaussian", "cubic"}) {
    const auto f = make_org("scattered", rows(data) + cat("kernel = \"", k, "\"\nshape = 3\n"));
    for (size_t i = 0; i < data.size(); ++i)
      expect_close(sample(*f, {data[i].u, data[i].v}).p, data[i].p, 1e-9, cat(k, ": point ", i));
  }
}

TEST(ScatteredOrg, ThinPlateReproducesAPlaneExactly) {
  // Data on the plane p(u, v) = a + b u + c v: the linear tail takes all of it, the weights are
  // zero, and the surface is that plane everywhere (with its normal), not only at the data.
  const Vec3 a{1, -2, 0.5}, b{3, 0.2, -1}, c{-0.4, -2.5, 0.7};
  std::vector<Datum> data;
  Rng rng(3, 1);
  for (int i = 0; i < 12; ++i) {
    const double u = rng.uniform(), v = rng.uniform();
    data.push_back({u, v, a + b * u + c * v});
  }
  const auto f = make_org("scattered", rows(data));
  const Vec3 n = normalize(cross(b, c));
  for (int i = 0; i < 50; ++i) {
    const double u = 1.4 * rng.uniform() - 0.2, v = 1.4 * rng.uniform() - 0.2;
    const SurfaceSample s = sample(*f, {u, v});
    const std::string at = cat(" at (", u, ", ", v, ")");
    expect_close(s.p, a + b * u + c * v, 1e-10, "p" + at);
    expect_close(s.dpdu, b, 1e-9, "dpdu" + at);
    expect_close(s.dpdv, c, 1e-9, "dpdv" + at);
    expect_close(s.n, n, 1e-9, "n" + at);
    EXPECT_LT(length(s.dpduu) + length(s.dpduv) + length(s.dpdvv), 1e-7) << at;
  }
}

TEST(ScatteredOrg, HeavySmoothingTendsToTheLeastSquaresPlane) {
  // lambda -> infinity drives the weights to zero: what is left is the polynomial tail fitted
  // by least squares (the normal equations of the linear tail, solved here directly).
  const auto data = random_data(15, 11);
  double M[3][3] = {}, r[3][3] = {};
  for (const Datum& d : data) {
    const double q[3] = {1, d.u, d.v};
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) M[i][j] += q[i] * q[j];
      for (int c = 0; c < 3; ++c) r[i][c] += q[i] * d.p[c];
    }
  }
  // Cramer's rule for the 3x3 system, per coordinate.
  const auto det = [](const double m[3][3]) {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  };
  Vec3 coef[3];
  for (int k = 0; k < 3; ++k)
    for (int c = 0; c < 3; ++c) {
      double m[3][3];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) m[i][j] = j == k ? r[i][c] : M[i][j];
      coef[k][c] = det(m) / det(M);
    }
  const auto f = make_org("scattered", rows(data) + "smoothing = 1e9\n");
  for (const Vec2 uv : {Vec2{0.2, 0.3}, Vec2{0.8, 0.6}, Vec2{0.5, 0.95}})
    expect_close(sample(*f, uv).p, coef[0] + coef[1] * uv.x + coef[2] * uv.y, 1e-6,
                 cat("at (", uv.x, ", ", uv.y, ")"));
  // Between the two: the misfit at the data grows with lambda, from (almost) zero.
  double last = -1;
  for (const char* lambda : {"1e-7", "1e-4", "1e-2", "1"}) {
    const auto g = make_org("scattered", rows(data) + cat("smoothing = ", lambda, "\n"));
    double sum = 0;
    for (const Datum& d : data) sum += length(sample(*g, {d.u, d.v}).p - d.p);
    EXPECT_GT(sum, last) << "smoothing " << lambda;
    if (last < 0) {
      EXPECT_GT(sum, 0) << "smoothing > 0 must not interpolate exactly";
      EXPECT_LT(sum, 1e-3) << "a tiny smoothing stays at the data";
    }
    last = sum;
  }
}

TEST(ScatteredOrg, NormalRaysLeaveTheSurfaceAlongItsNormal) {
  // org scattered + dir normal, through the camera: origins on the surface, unit directions
  // along the surface normal, differentials equal to neighbouring rays.
  VirtualCameraParts parts;
  const std::string p = rows(random_data(9, 5));
  parts.org = make_org("scattered", p);
  parts.dir = make_dir("normal", "");
  const VirtualCamera cam(std::move(parts));
  const auto f = make_org("scattered", p);
  const double h = 1e-6;
  for (const Vec2 uv : {Vec2{0.33, 0.41}, Vec2{0.71, 0.18}}) {
    const auto r = cam.generate_pinhole(uv), rv = cam.generate_pinhole({uv.x, uv.y + h}),
               rw = cam.generate_pinhole({uv.x, uv.y - h});
    ASSERT_TRUE(r && rv && rw);
    const SurfaceSample s = sample(*f, uv);
    expect_close(r->org, s.p, 1e-12, "origin");
    expect_close(r->dir, s.n, 1e-12, "direction");
    expect_close(r->ddir_dv, (rv->dir - rw->dir) / (2 * h), 1e-5, "ddir_dv");
  }
}

TEST(ScatteredSphere, MeetsEverySampleAndKeepsTheLayoutElsewhere) {
  // Directions pulled at three image positions; far from them (gaussian, narrow) the field is
  // the equidistant layout: straight ahead at the center, the horizon on the circle.
  const auto dir = make_dir("scattered_sphere",
                            "points = [[0.25, 0.3, 0.2, 0.5, -1], [0.8, 0.5, 1, 0.3, -0.2], "
                            "[0.5, 0.8, 0, -2, -2]]\nshape = 12\n");
  const SurfaceSample org{};
  const Vec3 want[3] = {normalize(Vec3{0.2, 0.5, -1}), normalize(Vec3{1, 0.3, -0.2}),
                        normalize(Vec3{0, -2, -2})};
  const Vec2 at[3] = {{0.25, 0.3}, {0.8, 0.5}, {0.5, 0.8}};
  for (int i = 0; i < 3; ++i) {
    DirSample d;
    ASSERT_TRUE(dir->eval(at[i], org, &d));
    expect_close(d.d, want[i], 1e-12, cat("sample ", i));
  }
  DirSample c, e;
  ASSERT_TRUE(dir->eval({0.5, 0.5}, org, &c));
  expect_close(c.d, {0, 0, -1}, 1e-12, "center");
  ASSERT_TRUE(dir->eval({0.5, 0.0}, org, &e));
  expect_close(e.d, {0, 1, 0}, 1e-12, "top of the circle");
  EXPECT_FALSE(dir->eval({0.02, 0.03}, org, &e)) << "a corner outside the circle has no ray";
}

TEST(ScatteredSphere, WithoutPullItIsTheFisheyePreset) {
  // Samples that ask for the layout's own directions pull nothing: every ray equals the 200
  // degree equidistant fisheye preset's on a square image.
  const double half = radians(100);
  std::string pts = "points = [";
  const Vec2 uv[4] = {{0.3, 0.3}, {0.7, 0.35}, {0.45, 0.8}, {0.9, 0.5}};
  for (int i = 0; i < 4; ++i) {
    const double x = 2 * uv[i].x - 1, y = 1 - 2 * uv[i].y, r = std::hypot(x, y), t = half * r;
    pts += cat(i ? ", [" : "[", uv[i].x, ", ", uv[i].y, ", ", std::sin(t) * x / r, ", ",
               std::sin(t) * y / r, ", ", -std::cos(t), "]");
  }
  VirtualCameraParts parts;
  parts.org = make_org("point", "");
  parts.dir = make_dir("scattered_sphere", pts + "]\nfov = 200\nkernel = \"thin_plate\"\n");
  const VirtualCamera ours(std::move(parts));
  const VirtualCamera preset(make_preset("fisheye", "fov = 200", {64, 64}));
  int compared = 0;
  for (int j = 0; j < 64; ++j)
    for (int i = 0; i < 64; ++i) {
      const Vec2 p{(i + 0.5) / 64, (j + 0.5) / 64};
      const auto a = ours.generate_pinhole(p), b = preset.generate_pinhole(p);
      ASSERT_EQ(bool(a), bool(b)) << "pixel " << i << ", " << j;
      if (!a) continue;
      expect_close(a->dir, b->dir, 1e-9, cat("pixel ", i, ", ", j));
      ++compared;
    }
  EXPECT_GT(compared, 3000);
}

TEST(ScatteredSphere, EquirectangularLayoutLooksWhereItsAnglesSay) {
  const auto dir = make_dir("scattered_sphere",
                            "points = [[0.1, 0.1, 0, 1, 0]]\nlayout = \"equirectangular\"\n"
                            "shape = 30\n");
  const SurfaceSample org{};
  const std::pair<Vec2, Vec3> expect[] = {{{0.5, 0.5}, {0, 0, -1}},
                                          {{0.75, 0.5}, {1, 0, 0}},
                                          {{0.25, 0.5}, {-1, 0, 0}},
                                          {{0.5, 0.25}, {0, std::sqrt(0.5), -std::sqrt(0.5)}}};
  for (const auto& [uv, want] : expect) {
    DirSample d;
    ASSERT_TRUE(dir->eval(uv, org, &d));
    expect_close(d.d, want, 1e-12, cat("at (", uv.x, ", ", uv.y, ")"));
  }
}

std::string error_of(const char* kind, const char* type, const std::string& toml) {
  try {
    if (std::string(kind) == "org")
      make_org(type, toml);
    else
      make_dir(type, toml);
  } catch (const ParamError& e) {
    EXPECT_EQ(e.key, "points") << e.what();
    return e.what();
  }
  ADD_FAILURE() << type << " accepted " << toml;
  return {};
}

TEST(ScatteredErrors, NameTheProblem) {
  const std::pair<std::string, std::string> cases[] = {
      {error_of("org", "scattered",
                "points = [[0.1, 0.2, 0, 0, 0], [0.5, 0.5, 1, 0, 0], "
                "[0.1, 0.2, 2, 0, 0]]"),
       "points 0 and 2 are at the same position"},
      {error_of("org", "scattered", "points = [[0.1, 0.2, 0, 0, 0], [0.5, 0.5, 1, 0, 0]]"),
       "at least 3 points are needed with this kernel, not 2"},
      {error_of("org", "scattered",
                "points = [[0.1, 0.1, 0, 0, 0], [0.5, 0.5, 1, 0, 0], [0.9, 0.9, 2, 0, 0]]"),
       "the points must not all lie on one line"},
      {error_of("org", "scattered", "points = [[0.1, 0.1, 0, 0], [0.5, 0.5, 1, 0, 0]]"),
       "point 0 has 4 numbers; each is [u, v, x, y, z]"},
      {error_of("dir", "scattered", "points = [[0.1, 0.1, 0, 0, 0]]\nkernel = \"gaussian\""),
       "point 0 has no direction"},
      {error_of("dir", "scattered_sphere", "points = [[0.02, 0.02, 0, 0, -1]]"),
       "point 0 lies outside the fisheye's image circle"},
  };
  std::vector<Datum> many = random_data(kRbfMaxPoints + 1, 2);
  EXPECT_NE(error_of("org", "scattered", rows(many)).find("at most 2000 points"),
            std::string::npos);
  many.pop_back();
  // (The largest system takes a minute unoptimized under the sanitizers: solved in Release.)
  if (!test::kSanitized) {
    EXPECT_NO_THROW(make_org("scattered", rows(many) + "kernel = \"gaussian\"\nshape = 30\n"));
  }
  for (const auto& [got, want] : cases) {
    EXPECT_NE(got.find(want), std::string::npos) << "got: " << got << "\nwanted: " << want;
  }
}

TEST(Rbf, SphereSitesOnOneCircleAreSingularUnderALinearTail) {
  // Under a linear tail in (x, y, z), sites on one circle of the sphere (one plane) leave the
  // tail undetermined.
  std::vector<Rbf<3>::Point> at;
  std::vector<Vec3> values;
  for (int i = 0; i < 6; ++i) {
    const double a = i * 2 * kPi / 6;
    at.push_back({std::cos(a) * 0.6, std::sin(a) * 0.6, -0.8});
    values.push_back({double(i), 0, 0});
  }
  try {
    Rbf<3> r(at, values, RbfKernel::ThinPlate);
    ADD_FAILURE() << "accepted coplanar sites";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("one plane"), std::string::npos) << e.what();
  }
  Rbf<3> g(at, values, RbfKernel::Gaussian, 2);  // no tail: fine
  EXPECT_NEAR(g.eval(at[3]).x, 3, 1e-12);
}

}  // namespace
}  // namespace anamorph

namespace anamorph {
namespace {

TEST(ScatteredCamera, InverseMapFindsThePixelOfEveryPoint) {
  // A composed camera has no closed-form inverse: project() searches numerically, which needs
  // the derivatives to be right. pixel -> ray -> a point along it -> project -> the pixel.
  for (const char* dir : {"normal", "scattered_sphere"}) {
    VirtualCameraParts parts;
    const bool sphere = std::string(dir) == "scattered_sphere";
    parts.org = sphere ? make_org("point", "") : make_org("scattered", rows(random_data(9, 5)));
    parts.dir = make_dir(dir, sphere ? "points = [[0.4, 0.45, 0.3, 0.1, -1], "
                                       "[0.7, 0.6, 0.6, -0.3, -0.6]]\nshape = 3\n"
                                     : "");
    const VirtualCamera cam(std::move(parts));
    for (const Vec2 uv : {Vec2{0.37, 0.42}, Vec2{0.61, 0.55}, Vec2{0.45, 0.7}}) {
      const auto r = cam.generate_pinhole(uv);
      ASSERT_TRUE(r) << dir;
      const Vec3 p = r->org + r->dir * 3.7;
      double best = 1;
      for (const Vec2 q : cam.project(p)) best = std::min(best, length(q - uv));
      EXPECT_LT(best, 1e-6) << dir << ": no image position of the point seen at (" << uv.x << ", "
                            << uv.y << ")";
    }
  }
}

}  // namespace
}  // namespace anamorph

namespace anamorph {
namespace {

// A point far outside the image was reported as collinear (u = 1e300: its coordinates swamped
// the rank test). Beyond kScatteredUvLimit it is out of range, for all three functions; at the
// limit, and with the largest shape, every kernel builds a surface whose rays are finite.
TEST(ScatteredErrors, FarPointsAreOutOfRangeNotCollinear) {
  const std::string corners =
      "points = [[0, 0, -1, 1, 0], [1, 0, 1, 1, 0], [0, 1, -1, -1, 0], [1, 1, 1, -1, 0.1], ";
  for (const char* far : {"1e300", "-1e300", "1000001"}) {
    const std::string pts = corners + "[" + far + ", 0.5, 0, 0, 1]]\n";
    for (const auto& got :
         {error_of("org", "scattered", pts), error_of("dir", "scattered", pts),
          error_of("dir", "scattered_sphere", pts + "layout = \"equirectangular\"\n")}) {
      EXPECT_NE(got.find("point 4: u = "), std::string::npos) << got;
      EXPECT_NE(got.find("is out of range (must be within [-1e+06, 1e+06]"), std::string::npos)
          << got;
      EXPECT_EQ(got.find("line"), std::string::npos) << got;
    }
  }
  EXPECT_NE(error_of("org", "scattered", corners + "[0.5, 1e300, 0, 0, 1]]\n").find("v = 1e+300"),
            std::string::npos);
  for (const std::string_view kernel : kRbfKernelNames)
    for (const char* shape : {"1e-3", "1", "1e50"}) {
      const std::string toml = corners + "[1e6, 0.5, 0, 0, 0.5], [0.5, -1e6, 0, 0, 0.5]]\n" +
                               cat("kernel = \"", kernel, "\"\nshape = ", shape, "\n");
      if (kernel != "thin_plate" && kernel != "cubic" && std::string(shape) == "1e-3")
        continue;  // (flat kernels over the image: too close together, and said so)
      std::unique_ptr<OrgFunction> f;
      ASSERT_NO_THROW(f = make_org("scattered", toml)) << toml;
      for (double u : {0.0, 0.25, 1.0})
        for (double v : {0.0, 0.5, 1.0}) {
          SurfaceSample s;
          ASSERT_TRUE(f->eval({u, v}, &s));
          EXPECT_TRUE(is_finite(s.p) && is_finite(s.dpdu) && is_finite(s.dpdv))
              << toml << " at " << u << ", " << v;
        }
    }
}

TEST(ScatteredErrors, ShapeLargerThanTheLimitIsOutOfRange) {
  try {
    make_org("scattered",
             "points = [[0, 0, 0, 0, 0], [1, 0, 1, 0, 0], [0, 1, 0, 1, 0]]\n"
             "kernel = \"multiquadric\"\nshape = 1e200\n");
    ADD_FAILURE() << "shape 1e200 accepted";
  } catch (const ParamError& e) {
    EXPECT_EQ(e.key, "shape");
    EXPECT_NE(std::string(e.what()).find("out of range"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace anamorph
