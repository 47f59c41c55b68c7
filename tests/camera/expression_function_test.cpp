// Expression origin and direction functions: analytic values, agreement with the built-in
// surfaces, errors naming the formula's key, and concurrent evaluation.
#include <gtest/gtest.h>

#include <cmath>
#include <thread>
#include <vector>

#include "camera/functions.h"
#include "function_test_util.h"

namespace anamorph {
namespace {

using test::cat;
using test::expect_close;
using test::sample;
using test::str;

TEST(ExpressionOrg, PlaneHasAnalyticValues) {
  const auto f = make_org("expression",
                          "x = \"u\"\ny = \"v\"\nz = \"0\"\nu_range = [-1, 3]\n"
                          "v_range = [2, 0]");
  for (int j = 0; j <= 10; ++j)
    for (int i = 0; i <= 10; ++i) {
      const Vec2 uv{i / 10.0, j / 10.0};
      const SurfaceSample s = sample(*f, uv);
      expect_close(s.p, {-1 + 4 * uv.x, 2 - 2 * uv.y, 0}, 1e-15, "p");
      expect_close(s.dpdu, {4, 0, 0}, 1e-9, "dpdu");
      expect_close(s.dpdv, {0, -2, 0}, 1e-9, "dpdv");
      // d/ds x d/dt of the formula's own parameters: (1,0,0) x (0,1,0), whatever the ranges.
      expect_close(s.n, {0, 0, 1}, 1e-12, "n");
      expect_close(s.dndu, {}, 1e-9, "dndu");
      expect_close(s.dpduu, {}, 1e-6, "dpduu");
      expect_close(s.dpduv, {}, 1e-6, "dpduv");
    }
}

TEST(ExpressionOrg, SphereFormulaEqualsSphereFunction) {
  const auto e =
      make_org("expression",
               "x = \"r * sin(u) * cos(v)\"\ny = \"r * sin(v)\"\nz = \"-r * cos(u) * cos(v)\"\n"
               "constants = { r = 2 }\nu_range = [-3, 2.5]\nv_range = [1.4, -1.2]");
  const auto s = make_org("sphere", cat("radius = 2\nu_range = [", degrees(-3), ", ", degrees(2.5),
                                        "]\nv_range = [", degrees(1.4), ", ", degrees(-1.2), "]"));
  for (const Vec2 uv : {Vec2{0.2, 0.3}, Vec2{0.5, 0.5}, Vec2{0.9, 0.8}}) {
    const SurfaceSample a = sample(*e, uv), b = sample(*s, uv);
    expect_close(a.p, b.p, 1e-14, "p");
    expect_close(a.dpdu, b.dpdu, 1e-7, "dpdu");
    expect_close(a.dpdv, b.dpdv, 1e-7, "dpdv");
    expect_close(a.dpduv, b.dpduv, 1e-6, "dpduv");
    // The formula's dp/du x dp/dv happens to point inward; the sphere's normal points outward.
    expect_close(a.n, -b.n, 1e-8, "n");
    expect_close(a.dndv, -b.dndv, 1e-6, "dndv");
  }
}

TEST(ExpressionOrg, NonFiniteFormulaIsNoRay) {
  const auto f = make_org("expression", "x = \"sqrt(u - 0.5)\"\ny = \"v\"\nz = \"0\"");
  SurfaceSample s;
  EXPECT_FALSE(f->eval({0.2, 0.5}, &s));
  EXPECT_TRUE(f->eval({0.8, 0.5}, &s));
}

TEST(ExpressionDir, NormalFormulaEqualsNormalDir) {
  const auto org = make_org("torus", "major_radius = 2\nminor_radius = 0.5");
  const auto e = make_dir("expression", "x = \"nx\"\ny = \"ny\"\nz = \"nz\"");
  const auto n = make_dir("normal");
  for (const Vec2 uv : {Vec2{0.2, 0.3}, Vec2{0.6, 0.55}}) {
    const SurfaceSample s = sample(*org, uv);
    DirSample a, b;
    ASSERT_TRUE(e->eval(uv, s, &a));
    ASSERT_TRUE(n->eval(uv, s, &b));
    expect_close(a.d, b.d, 1e-15, "d");
    expect_close(a.dd_du, b.dd_du, 1e-8, "dd_du");
    expect_close(a.dd_dv, b.dd_dv, 1e-8, "dd_dv");
  }
}

TEST(ExpressionDir, SeesOriginAndImagePosition) {
  const auto org = make_org("plane", "center = [1, 2, 3]");
  const auto e = make_dir("expression",
                          "x = \"ox + u\"\ny = \"oy * v\"\nz = \"oz - k\"\n"
                          "constants = { k = 10 }\nv_range = [0, 2]");
  const Vec2 uv{0.25, 0.75};
  const SurfaceSample s = sample(*org, uv);
  DirSample d;
  ASSERT_TRUE(e->eval(uv, s, &d));
  expect_close(d.d, {s.p.x + 0.25, s.p.y * 1.5, s.p.z - 10}, 1e-15, "d");
}

TEST(Expression, ErrorsNameTheFormula) {
  const auto key_of = [](auto&& make) -> std::string {
    try {
      make();
    } catch (const ParamError& e) {
      EXPECT_NE(std::string(e.what()), "") << "message";
      return e.key;
    }
    return "(no error)";
  };
  EXPECT_EQ(key_of([] { make_org("expression", "x = \"u\"\ny = \"v +\"\nz = \"0\""); }), "y");
  EXPECT_EQ(key_of([] { make_org("expression", "x = \"u\"\ny = \"v\"\nz = \"w\""); }), "z")
      << "unknown variable";
  EXPECT_EQ(key_of([] { make_org("expression", "x = \"\"\ny = \"v\"\nz = \"0\""); }), "x");
  EXPECT_EQ(key_of([] { make_org("expression", "x = \"u, v\"\ny = \"v\"\nz = \"0\""); }), "x")
      << "two values in one formula";
  EXPECT_EQ(key_of([] {
              make_org("expression", "x = \"u\"\ny = \"v\"\nz = \"0\"\nconstants = { u = 1 }");
            }),
            "constants")
      << "a constant hiding a variable";
  EXPECT_EQ(key_of([] {
              make_org("expression", "x = \"u\"\ny = \"v\"\nz = \"0\"\nconstants = { \"2x\" = 1 }");
            }),
            "constants");
  EXPECT_EQ(key_of([] { make_dir("expression", "x = \"nx\"\ny = \"ny\"\nz = \"q\""); }), "z");
  EXPECT_EQ(key_of([] { make_org("expression", "x = \"u\"\ny = \"v\""); }), "z") << "missing";
}

TEST(Expression, ConcurrentEvaluationGivesTheSameResults) {
  // Two origin functions and a direction function evaluated from several threads at once, each
  // thread interleaving them (the per-thread parser cache is keyed by instance), plus more
  // instances than the cache holds so that eviction happens.
  const auto a = make_org("expression",
                          "x = \"sin(u * k)\"\ny = \"v^2\"\nz = \"u * v\"\n"
                          "constants = { k = 3 }");
  const auto b = make_org("expression", "x = \"v\"\ny = \"cos(u)\"\nz = \"u - v\"");
  const auto d = make_dir("expression", "x = \"nx + ox\"\ny = \"ny * u\"\nz = \"nz - v\"");
  std::vector<std::unique_ptr<OrgFunction>> extra;
  for (int k = 0; k < 12; ++k)
    extra.push_back(make_org("expression", cat("x = \"u + ", k, "\"\ny = \"v\"\nz = \"0\"")));

  constexpr int kN = 4000;
  const auto run = [&](std::vector<double>* out) {
    out->clear();
    for (int i = 0; i < kN; ++i) {
      const Vec2 uv{(i % 61) / 60.0, (i % 37) / 36.0};
      const SurfaceSample sa = sample(*a, uv), sb = sample(*b, uv);
      DirSample dd;
      EXPECT_TRUE(d->eval(uv, sa, &dd));
      const SurfaceSample se = sample(*extra[size_t(i) % extra.size()], uv);
      for (const Vec3& v : {sa.p, sa.n, sb.p, sb.dpdv, dd.d, dd.dd_du, se.p})
        out->insert(out->end(), {v.x, v.y, v.z});
    }
  };
  std::vector<double> reference;
  run(&reference);
  std::vector<std::vector<double>> results(6);
  std::vector<std::thread> threads;
  for (auto& r : results) threads.emplace_back(run, &r);
  for (auto& t : threads) t.join();
  for (size_t t = 0; t < results.size(); ++t) {
    ASSERT_EQ(results[t].size(), reference.size());
    for (size_t k = 0; k < reference.size(); ++k)
      ASSERT_EQ(results[t][k], reference[k]) << "thread " << t << " value " << k;
  }
}

}  // namespace
}  // namespace anamorph
