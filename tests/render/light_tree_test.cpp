// The light tree (render/light_tree.h) and the path tracer's pick (render/light_pick.cpp):
// probabilities that sum to at most one, sampling that agrees bit for bit with the pmf used for
// MIS, zero only where a light cannot reach the point, a bounded depth, and on a hundred point
// lights an estimator that stays exact in expectation with far less variance than picking by power.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "accel/accel.h"
#include "render/light_tree.h"
#include "render/lights.h"
#include "scene/scene_loader.h"

namespace anamorph {

namespace {

LightBounds point_light(const Vec3& p, double phi) {
  LightBounds b;
  b.box.extend(p);
  b.phi = phi;
  b.cos_o = -1;
  return b;
}

LightBounds triangle(const Vec3& a, const Vec3& b, const Vec3& c, double phi, bool two_sided) {
  LightBounds l;
  l.box.extend(a);
  l.box.extend(b);
  l.box.extend(c);
  l.phi = phi;
  l.w = normalize(cross(b - a, c - a));
  l.two_sided = two_sided;
  return l;
}

// Points, spots, one- and two-sided triangles and spheres scattered over a 10-unit box.
std::vector<LightBounds> mixed_lights(int count, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-5, 5), s(0.05, 0.5), phi(0.1, 10);
  std::vector<LightBounds> out;
  for (int i = 0; i < count; ++i) {
    const Vec3 c(u(rng), u(rng), u(rng));
    const Vec3 e1(s(rng), s(rng) - 0.25, s(rng)), e2(s(rng) - 0.25, s(rng), -s(rng));
    switch (i % 4) {
      case 0:
        out.push_back(point_light(c, phi(rng)));
        break;
      case 1: {
        LightBounds spot = point_light(c, phi(rng));
        spot.cos_o = 1;
        spot.w = normalize(Vec3(u(rng), u(rng), u(rng)));
        spot.cos_e = std::cos(0.6);
        out.push_back(spot);
        break;
      }
      case 2:
        out.push_back(triangle(c, c + e1, c + e2, phi(rng), i % 8 == 2));
        break;
      default: {
        LightBounds sphere = point_light(c, phi(rng));
        sphere.box.extend(c + Vec3(0.3, 0.3, 0.3));
        sphere.box.extend(c - Vec3(0.3, 0.3, 0.3));
        out.push_back(sphere);
      }
    }
  }
  return out;
}

}  // namespace

TEST(LightTree, PmfsSumToAtMostOneAndSamplingAgreesWithThemBitForBit) {
  std::mt19937 rng(7);
  const std::vector<LightBounds> lights = mixed_lights(61, rng);
  const LightTree tree(lights);
  std::uniform_real_distribution<double> u(-6, 6);
  constexpr int kStrata = 4096;
  for (int trial = 0; trial < 12; ++trial) {
    const Vec3 p(u(rng), u(rng), u(rng)), n = normalize(Vec3(u(rng), u(rng), u(rng)));
    double sum = 0;
    std::vector<double> pmf(lights.size());
    for (uint32_t i = 0; i < lights.size(); ++i) sum += pmf[i] = tree.pmf(i, p, &n);
    // Below 1 where a node's bounds reach p but neither child's does (two spots whose cones'
    // union holds p): sample() then fails, which only loses lights that give p nothing.
    EXPECT_LE(sum, 1 + 1e-12) << "at trial " << trial;
    for (uint32_t i = 0; i < lights.size(); i += 4)
      EXPECT_GT(pmf[i], 0) << "point light " << i << " reaches every point, at trial " << trial;
    // Stratified numbers: each light's share of [0, 1) is an interval of length pmf, and the
    // failures' share 1 - sum (within the strata's width at their ends).
    std::vector<int> count(lights.size());
    int failed = 0;
    for (int k = 0; k < kStrata; ++k) {
      uint32_t l;
      double q;
      if (!tree.sample((k + 0.5) / kStrata, p, &n, &l, &q)) {
        ++failed;
        continue;
      }
      ASSERT_EQ(q, pmf[l]) << "light " << l << ": sample's pmf and pmf() differ";
      ++count[l];
    }
    for (uint32_t i = 0; i < lights.size(); ++i)
      EXPECT_NEAR(count[i] / double(kStrata), pmf[i], 2.0 / kStrata) << "light " << i;
    EXPECT_NEAR(failed / double(kStrata), 1 - sum, 2.0 * lights.size() / kStrata);
  }
}

TEST(LightTree, ZeroOnlyWhereALightCannotReachThePoint) {
  // A one-sided triangle facing +z, a spot looking down -z with a 30 degree cone, a point light.
  std::vector<LightBounds> lights = {triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 1, false),
                                     point_light({5, 0, 0}, 1), point_light({-5, 0, 0}, 1)};
  lights[1].cos_o = 1;
  lights[1].w = {0, 0, -1};
  lights[1].cos_e = std::cos(0.5236);
  const LightTree tree(lights);
  const Vec3 up(0, 0, 1);
  EXPECT_GT(tree.pmf(0, {0.2, 0.2, 3}, &up), 0) << "in front of the triangle";
  EXPECT_EQ(tree.pmf(0, {0.2, 0.2, -3}, &up), 0) << "behind the one-sided triangle";
  EXPECT_GT(tree.pmf(1, {5, 0, -3}, &up), 0) << "inside the spot's cone";
  EXPECT_EQ(tree.pmf(1, {5, 3, -1}, &up), 0) << "outside the spot's cone (72 degrees off)";
  EXPECT_GT(tree.pmf(2, {5, 3, -1}, &up), 0) << "a point light reaches everywhere";
}

TEST(LightTree, CoincidentLightsKeepTheTreeShallow) {
  std::vector<LightBounds> lights(5000, point_light({1, 2, 3}, 1));
  const LightTree tree(lights);
  EXPECT_LE(tree.depth(), 14) << "5000 lights at one point: a balanced split";
  const Vec3 p(0, 0, 0), n(0, 1, 0);
  EXPECT_DOUBLE_EQ(tree.pmf(1234, p, &n), tree.pmf(17, p, &n));
}

// A hundred point lights of equal intensity on a 10 x 10 grid 1 unit above a 30-unit floor,
// seen from one corner: the one-light estimator of the direct irradiance f_l / pmf_l is exact in
// expectation (no light that gives the point something has pmf 0), and its variance is far below
// that of picking by power (pmf 1/100), computed exactly from the pmfs.
TEST(LightTree, ManyPointLightsPickedByWhatTheyGiveThePoint) {
  std::string toml = "[image]\nwidth = 1\nheight = 1\n";
  for (int i = 0; i < 100; ++i)
    toml += "[[light]]\ntype = \"point\"\nintensity = 1\nposition = [" +
            std::to_string(-15 + 3 * (i % 10)) + ", 1, " + std::to_string(-15 + 3 * (i / 10)) +
            "]\n";
  const Scene scene = load_scene_from_string(toml, "test.toml");
  const Accel accel(scene);
  const Lights lights(scene, accel);
  ASSERT_EQ(lights.count(), 100u);
  const Vec3 p(-14, 0, -14), n(0, 1, 0);
  double exact = 0, tree_second = 0, power_second = 0;
  for (size_t i = 0; i < 100; ++i) {
    const Vec3 q(-15 + 3 * double(i % 10), 1, -15 + 3 * double(i / 10));
    const Vec3 d = q - p;
    const double f = dot(normalize(d), n) / length_squared(d);
    const double pmf = lights.pick_pmf(i, p, n);
    ASSERT_GT(pmf, 0) << "light " << i << " lights the point";
    exact += f;
    tree_second += f * f / pmf;
    power_second += f * f * 100;
  }
  const double tree_var = tree_second - exact * exact, power_var = power_second - exact * exact;
  EXPECT_LT(tree_var, 0.05 * power_var) << "relative variance: tree " << tree_var / (exact * exact)
                                        << ", by power " << power_var / (exact * exact);
  size_t index;
  double pmf;
  ASSERT_TRUE(lights.pick(0.5, p, n, &index, &pmf));
  EXPECT_EQ(pmf, lights.pick_pmf(index, p, n));
}

}  // namespace anamorph
