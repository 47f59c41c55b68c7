// Ray tables (camera/ray_table.h, org and dir `table`): exact at the samples, quadratics
// reproduced between them, holes as no-ray regions with smooth rays around them, and errors.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "camera/functions.h"
#include "camera/ray_table.h"
#include "function_test_util.h"

namespace anamorph {
namespace {

using test::cat;
using test::expect_close;

// A quadratic field of image (u, v).
Vec3 quadratic(double u, double v) {
  return {1 + 2 * u - v + 0.5 * u * u, -u * v + 3 * v * v, 0.25 - u + 2 * v - u * u + u * v};
}
Vec3 quadratic_du(double u, double v) { return {2 + u, -v, -1 - 2 * u + v}; }
Vec3 quadratic_dv(double u, double v) { return {-1, -u + 6 * v, 2 + u}; }

RayTableData sampled(int w, int h) {
  RayTableData d{w, h, {}, {}};
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) d.values.push_back(quadratic((i + 0.5) / w, (j + 0.5) / h));
  return d;
}

TEST(RayTable, ExactAtSamplesAndReproducesQuadraticsBetweenThem) {
  const RayTable t(sampled(12, 9));
  Vec3 f, fu, fv;
  for (int j = 0; j < 9; ++j)
    for (int i = 0; i < 12; ++i) {
      const double u = (i + 0.5) / 12, v = (j + 0.5) / 9;
      ASSERT_TRUE(t.eval(u, v, &f, &fu, &fv));
      expect_close(f, quadratic(u, v), 1e-14, cat("sample ", i, ", ", j));
    }
  // Catmull-Rom has approximation order 3: where the whole 4 x 4 stencil is real samples it
  // reproduces a quadratic exactly, with its derivatives.
  for (const Vec2 uv : {Vec2{0.31, 0.42}, Vec2{0.5, 0.5}, Vec2{0.7, 0.61}, Vec2{0.26, 0.7}}) {
    ASSERT_TRUE(t.eval(uv.x, uv.y, &f, &fu, &fv));
    const std::string at = cat(" at (", uv.x, ", ", uv.y, ")");
    expect_close(f, quadratic(uv.x, uv.y), 1e-12, "value" + at);
    expect_close(fu, quadratic_du(uv.x, uv.y), 1e-10, "d/du" + at);
    expect_close(fv, quadratic_dv(uv.x, uv.y), 1e-10, "d/dv" + at);
  }
}

TEST(RayTable, HolesGiveNoRayAndSmoothRaysAroundThem) {
  RayTableData d = sampled(16, 16);
  d.valid.assign(256, true);
  for (int j = 6; j <= 8; ++j)
    for (int i = 5; i <= 9; ++i) d.valid[size_t(j * 16 + i)] = false;  // a 5 x 3 hole
  const RayTable t(d);
  Vec3 f, fu, fv;
  EXPECT_FALSE(t.eval(7.5 / 16, 7.5 / 16, &f, &fu, &fv)) << "the hole's center";
  EXPECT_FALSE(t.eval(5.5 / 16, 6.5 / 16, &f, &fu, &fv)) << "an invalid sample";
  ASSERT_TRUE(t.eval(4.5 / 16, 7.5 / 16, &f, &fu, &fv)) << "the valid sample beside it";
  expect_close(f, quadratic(4.5 / 16, 7.5 / 16), 1e-14, "a valid sample keeps its value");
  // Halfway between a valid and an invalid sample is the boundary; just inside it the ray is
  // the smooth continuation (the hole's samples were extrapolated linearly, so within a
  // quadratic's curvature of the truth), never a jump.
  ASSERT_TRUE(t.eval(4.9 / 16, 7.5 / 16, &f, &fu, &fv));
  // (Linear extrapolation misses a quadratic by about |f''| h^2 <= 6 / 256.)
  expect_close(f, quadratic(4.9 / 16, 7.5 / 16), 0.025, "near the hole");
  EXPECT_FALSE(t.eval(5.1 / 16, 7.5 / 16, &f, &fu, &fv));
  // Every ray everywhere is finite.
  for (int j = 0; j < 64; ++j)
    for (int i = 0; i < 64; ++i)
      if (t.eval((i + 0.5) / 64, (j + 0.5) / 64, &f, &fu, &fv)) {
        ASSERT_TRUE(std::isfinite(f.x + f.y + f.z + fu.x + fu.y + fu.z + fv.x + fv.y + fv.z))
            << i << ", " << j;
      }
}

std::string inline_samples(int w, int h) {
  std::string s = "samples = [";
  for (int j = 0; j < h; ++j) {
    s += j ? ", [" : "[";
    for (int i = 0; i < w; ++i) {
      const Vec3 p = quadratic((i + 0.5) / w, (j + 0.5) / h);
      s += cat(i ? ", [" : "[", p.x, ", ", p.y, ", ", p.z, "]");
    }
    s += "]";
  }
  return s + "]\n";
}

TEST(TableFunctions, InlineOrgAndDirInterpolateTheSamples) {
  const auto org = make_org("table", inline_samples(6, 5));
  SurfaceSample s;
  ASSERT_TRUE(org->eval({0.5, 0.5}, &s));
  expect_close(s.p, quadratic(0.5, 0.5), 1e-12, "org");
  EXPECT_EQ(length(s.n), 0) << "a table has no normal";
  const auto dir = make_dir("table", inline_samples(6, 5));
  DirSample d;
  ASSERT_TRUE(dir->eval({0.5, 0.5}, s, &d));
  expect_close(d.d, quadratic(0.5, 0.5), 1e-12, "dir");
}

std::string error_of(const std::string& toml) {
  try {
    make_dir("table", toml);
  } catch (const ParamError& e) {
    return e.key + ": " + e.what();
  }
  return "<accepted>";
}

TEST(TableFunctions, ErrorsNameTheKey) {
  const std::pair<std::string, std::string> cases[] = {
      {"", "give either file or samples"},
      {"file = \"x.exr\"\n" + inline_samples(2, 2), "give either file or samples"},
      {"samples = [[[0, 0, -1], [1, 0, -1]], [[0, 1, -1]]]",
       "samples: row 1 has 1 samples, row 0 has 2"},
      {inline_samples(2, 2) + "valid = [[1, 1]]", "valid has 1 rows, samples 2"},
      {inline_samples(2, 2) + "valid = [[0, 0], [0, 0]]", "the table has no valid sample"},
      {inline_samples(2, 2) + "layer = \"dir\"", "layer is only used with file"},
  };
  for (const auto& [toml, want] : cases) {
    const std::string got = error_of(toml);
    EXPECT_NE(got.find(want), std::string::npos) << "got: " << got << "\nwanted: " << want;
  }
}

}  // namespace
}  // namespace anamorph
