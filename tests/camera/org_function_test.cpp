// Properties every origin function must have: analytic derivatives equal finite differences,
// unit normals orthogonal to the surface, range reversal mirrors the image, flip_normal flips,
// and eval_batch agrees with eval bit for bit.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "camera/functions.h"
#include "function_test_util.h"

namespace anamorph {
namespace {

using test::expect_close;
using test::sample;
using test::str;

struct Case {
  const char* name;              // test label
  const char* type;              // registry name
  std::string toml;              // keys other than the ranges
  std::string u_range, v_range;  // "[a, b]" (empty: the function has no ranges)
  double tol = 1e-6;             // derivative tolerance
  bool has_normal = true;
  bool image_coordinates = false;  // no ranges, data placed at image (u, v) (scattered)
};

// A wavy control net as TOML rows: nu points per row, nv rows, z = f(x, y).
std::string net(int nu, int nv) {
  std::string rows = "[";
  for (int j = 0; j < nv; ++j) {
    rows += j ? ", [" : "[";
    for (int i = 0; i < nu; ++i) {
      const double x = i - 0.3 * j, y = -j + 0.1 * i * i, z = std::sin(1.3 * i + 0.7 * j) + 0.2 * i;
      rows += test::cat(i ? ", [" : "[", x, ", ", y, ", ", z, "]");
    }
    rows += "]";
  }
  return rows + "]";
}
std::string weights(int nu, int nv) {
  std::string rows = "[";
  for (int j = 0; j < nv; ++j) {
    rows += j ? ", [" : "[";
    for (int i = 0; i < nu; ++i)
      rows += test::cat(i ? ", " : "", 0.5 + 0.3 * ((i * 7 + j * 3) % 5));
    rows += "]";
  }
  return rows + "]";
}

// A parallelogram as an OBJ file (two triangles), written once per test run and removed at exit.
std::string quad_obj() {
  struct File {
    std::filesystem::path path = std::filesystem::temp_directory_path() /
                                 test::cat("anamorph_org_test_", ::getpid(), ".obj");
    File() {
      std::ofstream o(path);
      o << "v 0 0 -2\nv 2 0 -1\nv 2.5 1.5 -1\nv 0.5 1.5 -2\n"
           "vt 0.1 0.2\nvt 0.9 0.2\nvt 0.9 0.8\nvt 0.1 0.8\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";
    }
    ~File() { std::filesystem::remove(path); }
  };
  static const File f;
  return f.path.string();
}

// Nine [u, v, x, y, z] rows at scattered image positions (none at kPoints below), z wavy.
std::string scattered_points() {
  const double uv[9][2] = {{0.1, 0.15}, {0.5, 0.05}, {0.92, 0.2}, {0.2, 0.5},  {0.55, 0.45},
                           {0.9, 0.6},  {0.05, 0.9}, {0.4, 0.95}, {0.75, 0.85}};
  std::string rows = "[";
  for (int i = 0; i < 9; ++i) {
    const double u = uv[i][0], v = uv[i][1];
    rows += test::cat(i ? ", [" : "[", u, ", ", v, ", ", 2 * u + 0.3 * v, ", ", -2 * v, ", ",
                      std::sin(3 * u) + v * v, "]");
  }
  return rows + "]";
}

std::vector<Case> cases() {
  return {
      {"point", "point", "position = [1, 2, 3]", "", "", 1e-6, false},
      {"plane", "plane", "center = [1, 2, 3]\nedge_u = [2, 0, 1]\nedge_v = [0, -1, 0.5]",
       "[0.1, 0.9]", "[-0.2, 1.3]"},
      {"plane_size", "plane", "size = [3, 2]\nnormal = [1, 0, -1]\nup = [0, 1, 0.2]", "[0, 1]",
       "[0, 1]"},
      {"sphere", "sphere",
       "center = [1, -2, 0.5]\nradius = 2\naxis = [0.3, 1, 0.2]\nfront = [1, 0, -1]", "[-150, 120]",
       "[80, -70]"},
      {"cylinder", "cylinder", "center = [0, 0, 0]\naxis = [1, -1, -1]\nradius = 1.5",
       "[-170, 160]", "[2, -1]"},
      {"cone", "cone", "apex = [1, 1, 1]\naxis = [0, 0, 1]\nhalf_angle = 30", "[-180, 170]",
       "[2, 0.2]"},
      {"torus", "torus",
       "center = [0, 1, 0]\naxis = [1, 1, 0]\nmajor_radius = 2\nminor_radius = 0.5", "[-160, 180]",
       "[170, -170]"},
      {"ellipsoid", "ellipsoid", "center = [0, 0, -3]\nradii = [1, 2, 3]\naxis = [0, 1, 1]",
       "[-150, 120]", "[80, -85]"},
      {"quadric_sphere", "quadric",
       "matrix = [[1, 0.5, 0], [0.2, 2, 0.3], [0, -0.4, 1.5]]\ntranslation = [1, 2, 3]",
       "[-150, 120]", "[80, -85]"},
      {"quadric_mirror", "quadric", "matrix = [[-1, 0.5, 0], [0.2, 2, 0.3], [0, -0.4, 1.5]]",
       "[-150, 120]", "[80, -85]"},
      {"hyperboloid1", "quadric",
       "kind = \"hyperboloid_one_sheet\"\nmatrix = [[1, 0, 0.3], [0, 2, 0], [0, 0, 1]]",
       "[-150, 120]", "[1.2, -0.8]"},
      {"hyperboloid2", "quadric", "kind = \"hyperboloid_two_sheets\"", "[-150, 120]", "[1.2, 0.1]"},
      {"paraboloid", "quadric", "kind = \"paraboloid\"\ntranslation = [0, -1, 0]", "[-150, 120]",
       "[1.5, 0.1]"},
      {"superquadric", "superquadric",
       "radii = [1, 2, 0.5]\nexponent_ns = 1.5\nexponent_ew = 0.7\naxis = [0, 1, 1]", "[-150, 120]",
       "[75, -80]"},
      {"superquadric_round", "superquadric", "exponent_ns = 0.3\nexponent_ew = 1.8", "[-150, 120]",
       "[75, -80]"},
      {"bezier", "bezier", test::cat("points = ", net(4, 3)), "[0.1, 0.95]", "[0, 1]"},
      {"bezier_rational", "bezier",
       test::cat("points = ", net(3, 5), "\nweights = ", weights(3, 5)), "[0, 1]", "[0.2, 0.9]"},
      {"bspline", "bspline", test::cat("points = ", net(6, 5), "\ndegree_u = 3\ndegree_v = 2"),
       "[0.05, 0.9]", "[0, 1]"},
      {"bspline_uniform", "bspline",
       test::cat("points = ", net(7, 6),
                 "\ndegree_u = 2\ndegree_v = 3\nknot_type_u = \"uniform\"\n"
                 "knot_type_v = \"uniform\""),
       "[0, 1]", "[0, 1]"},
      {"bspline_explicit", "bspline",
       test::cat("points = ", net(6, 5),
                 "\ndegree_u = 3\ndegree_v = 2\nknots_u = [0, 0, 0, 0, 0.3, 0.4, 2, 2, 2, 2]\n"
                 "knots_v = [-1, -1, -1, 0, 0, 3, 3, 3]"),
       "[0, 1]", "[1, 0]"},
      {"nurbs", "nurbs",
       test::cat("points = ", net(5, 4), "\nweights = ", weights(5, 4),
                 "\ndegree_u = 3\ndegree_v = 2\nknots_u = [0, 0, 0, 0, 0.6, 1, 1, 1, 1]"),
       "[0, 1]", "[0, 1]"},
      {"mesh", "mesh", test::cat("file = \"", quad_obj(), "\""), "[0.15, 0.85]", "[0.75, 0.25]"},
      {"expression", "expression",
       "x = \"u + a * sin(v)\"\ny = \"v^2 - u * v\"\nz = \"k * cos(u) + u * v^2\"\n"
       "constants = { a = 0.5, k = 2 }",
       "[-1, 2]", "[0.5, -1.5]", 2e-5},
      {"scattered_thin_plate", "scattered", test::cat("points = ", scattered_points()), "", "",
       1e-6, true, true},
      {"scattered_multiquadric", "scattered",
       test::cat("points = ", scattered_points(), "\nkernel = \"multiquadric\"\nshape = 2"), "", "",
       1e-6, true, true},
      {"scattered_gaussian_smoothed", "scattered",
       test::cat("points = ", scattered_points(),
                 "\nkernel = \"gaussian\"\nshape = 1.5\nsmoothing = 0.01"),
       "", "", 1e-6, true, true},
      {"scattered_cubic", "scattered",
       test::cat("points = ", scattered_points(), "\nkernel = \"cubic\""), "", "", 1e-6, true,
       true},
      {"table", "table", test::cat("samples = ", net(7, 6)), "", "", 1e-6, false, true},
  };
}

std::unique_ptr<OrgFunction> build(const Case& c, bool rev_u = false, bool rev_v = false,
                                   const std::string& extra = "") {
  std::string t = test::cat(c.toml, "\n", extra, "\n");
  const auto rev = [](const std::string& r) {  // "[a, b]" -> "[b, a]"
    const auto comma = r.find(',');
    return test::cat("[", r.substr(comma + 1, r.size() - comma - 2), ", ", r.substr(1, comma - 1),
                     "]");
  };
  if (!c.u_range.empty()) t += test::cat("u_range = ", rev_u ? rev(c.u_range) : c.u_range, "\n");
  if (!c.v_range.empty()) t += test::cat("v_range = ", rev_v ? rev(c.v_range) : c.v_range, "\n");
  return make_org(c.type, t);
}

void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

// Away from knots of the spline cases (second derivatives jump there).
const Vec2 kPoints[] = {{0.3, 0.35}, {0.62, 0.7}, {0.83, 0.22}, {0.47, 0.56}, {0.07, 0.93}};

class OrgFunctionTest : public ::testing::TestWithParam<Case> {};

TEST_P(OrgFunctionTest, DerivativesMatchFiniteDifferences) {
  const auto f = build(GetParam());
  for (const Vec2 uv : kPoints) test::expect_derivatives_match(*f, uv, GetParam().tol);
}

TEST_P(OrgFunctionTest, NormalIsUnitAndOrthogonal) {
  if (!GetParam().has_normal) {
    const SurfaceSample s = sample(*build(GetParam()), {0.3, 0.3});
    EXPECT_EQ(length(s.n), 0) << "a function without surface reports a zero normal";
    return;
  }
  const auto f = build(GetParam());
  for (const Vec2 uv : kPoints) test::expect_normal_valid(*f, uv, 1e-9);
}

TEST_P(OrgFunctionTest, ReversedRangesMirrorTheImage) {
  const Case& c = GetParam();
  if (c.image_coordinates) return;  // data at image positions: no ranges to reverse
  if (c.u_range.empty()) {
    // Without ranges the function does not depend on (u, v) at all.
    const auto f = build(c);
    for (const Vec2 uv : kPoints) expect_close(sample(*f, uv).p, sample(*f, {0, 0}).p, 0, "p");
    return;
  }
  const auto f = build(c), fu = build(c, true, false), fv = build(c, false, true);
  for (const Vec2 uv : kPoints) {
    const SurfaceSample s = sample(*f, uv);
    const SurfaceSample su = sample(*fu, {1 - uv.x, uv.y}), sv = sample(*fv, {uv.x, 1 - uv.y});
    expect_close(su.p, s.p, 1e-12, "u-reversed p");
    expect_close(sv.p, s.p, 1e-12, "v-reversed p");
    expect_close(su.dpdu, -s.dpdu, 1e-9, "u-reversed dpdu");
    expect_close(sv.dpdv, -s.dpdv, 1e-9, "v-reversed dpdv");
    expect_close(su.dpdv, s.dpdv, 1e-9, "u-reversed dpdv");
    // Mirroring the parameter never turns the surface around.
    expect_close(su.n, s.n, 1e-9, "u-reversed n");
    expect_close(sv.n, s.n, 1e-9, "v-reversed n");
    expect_close(su.dndu, -s.dndu, 1e-6, "u-reversed dndu");
    expect_close(sv.dndv, -s.dndv, 1e-6, "v-reversed dndv");
  }
}

TEST_P(OrgFunctionTest, FlipNormalReversesNormalOnly) {
  const Case& c = GetParam();
  if (!c.has_normal) {
    try {
      build(c, false, false, "flip_normal = true");
      ADD_FAILURE() << c.type << " has no normal, so flip_normal must be an unknown key";
    } catch (const ParamError& e) {
      EXPECT_EQ(e.key, "flip_normal");
    }
    return;
  }
  const auto f = build(c), g = build(c, false, false, "flip_normal = true");
  for (const Vec2 uv : kPoints) {
    const SurfaceSample a = sample(*f, uv), b = sample(*g, uv);
    expect_close(b.p, a.p, 0, "p");
    expect_close(b.dpdu, a.dpdu, 0, "dpdu");
    expect_close(b.n, -a.n, 0, "n");
    expect_close(b.dndu, -a.dndu, 0, "dndu");
    expect_close(b.dndv, -a.dndv, 0, "dndv");
  }
}

TEST_P(OrgFunctionTest, EvalBatchMatchesEvalBitForBit) {
  const auto f = build(GetParam());
  // A 4x4 packet of pixel centers, then a partial packet with repeats and the domain ends.
  std::vector<Vec2> at;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) at.push_back({(100 + i + 0.5) / 640, (37 + j + 0.5) / 480});
  for (double u : {0.0, 0.1, 0.25, 0.26, 0.7, 1.0, 0.4})
    for (double v : {0.05, 0.5, 0.95}) at.push_back({u, v});
  std::vector<bool> ok;
  const std::vector<SurfaceSample> batch = test::batch_samples(*f, at, &ok);
  for (size_t i = 0; i < at.size(); ++i) {
    SurfaceSample s;
    const bool eval_ok = f->eval(at[i], &s);
    const std::string where =
        test::cat("lane ", i % kCameraBatch, " at (", at[i].x, ", ", at[i].y, ")");
    EXPECT_EQ(bool(ok[i]), eval_ok) << where;
    if (eval_ok) test::expect_same_bits(batch[i], s, where);
  }
}

INSTANTIATE_TEST_SUITE_P(All, OrgFunctionTest, ::testing::ValuesIn(cases()),
                         [](const auto& p) { return std::string(p.param.name); });

// Every registered origin function appears in the table above at least once.
TEST(OrgFunctionTest, EveryRegisteredFunctionIsCovered) {
  const auto all = cases();
  for (const auto& f : org_functions()) {
    bool found = false;
    for (const auto& c : all) found |= f.name == c.type;
    EXPECT_TRUE(found) << "origin function '" << f.name << "' has no case in org_function_test";
  }
}

}  // namespace
}  // namespace anamorph
