// The BSDF's clear coat and sheen layers (layers.cpp, glTF KHR_materials_clearcoat and _sheen):
// importance sampling agrees with eval / pdf, layered surfaces reflect at most what reaches
// them, the coat over a black base is a GGX dielectric of F0 0.04, and the sheen albedo table
// agrees with a Monte Carlo integral of the lobe.
#include <gtest/gtest.h>

#include <cmath>

#include "material/bsdf.h"
#include "math/rng.h"
#include "math/sampling.h"

namespace anamorph {
namespace {

Bsdf layered(Color base, double coat, double coat_rough, Color sheen, double sheen_rough) {
  Bsdf b;
  b.frame = Frame::from_normal({0, 0, 1});
  b.ng = {0, 0, 1};
  b.diffuse = base;
  b.coat = coat;
  b.coat_alpha = std::max(coat_rough * coat_rough, 1e-3);
  b.coat_frame = b.frame;
  b.sheen = sheen;
  b.sheen_roughness = sheen_rough;
  return b;
}

Vec3 from_cos(double mu) { return {std::sqrt(1 - mu * mu), 0, mu}; }

// Directional albedo two ways: the mean of sample()'s weights, and eval() x cos integrated with
// uniform hemisphere directions.
struct Albedo {
  double sampled, integrated;
};
Albedo albedo(const Bsdf& b, const Vec3& wo, int n) {
  Rng rng = Rng::for_sample(1, 2, 3, 7);
  double s = 0, e = 0;
  for (int i = 0; i < n; ++i) {
    Vec2 u;
    rng.uniform2(u.x, u.y);
    BsdfSample bs;
    if (b.sample(wo, u, rng.uniform(), &bs)) s += luminance(bs.weight);
    rng.uniform2(u.x, u.y);
    const double z = u.x, r = std::sqrt(std::max(0.0, 1 - z * z)), phi = 2 * kPi * u.y;
    const Vec3 wi{r * std::cos(phi), r * std::sin(phi), z};
    e += luminance(b.eval(wo, wi)) * z * 2 * kPi;
  }
  return {s / n, e / n};
}

TEST(BsdfLayers, SamplingAgreesWithEvalAndStaysBelowOne) {
  const struct {
    const char* what;
    Bsdf b;
  } cases[] = {
      {"rough coat over white", layered({1, 1, 1}, 1, 0.4, {0, 0, 0}, 0)},
      {"sheen over white", layered({1, 1, 1}, 0, 0, {1, 1, 1}, 0.5)},
      {"coat and sheen over grey", layered({0.5, 0.5, 0.5}, 0.7, 0.5, {0.8, 0.6, 0.4}, 0.3)},
  };
  for (const auto& c : cases)
    for (double mu : {0.9, 0.5, 0.2}) {
      const Albedo a = albedo(c.b, from_cos(mu), 50000);
      // 50000 samples: standard errors below 0.005 for these smooth lobes.
      EXPECT_NEAR(a.sampled, a.integrated, 0.01) << c.what << ", cos theta_o " << mu;
      EXPECT_LE(a.integrated, 1.0 + 0.01) << c.what << ", cos theta_o " << mu;
    }
}

// GGX reflection sampled by its visible normals: the density agrees with a histogram of the
// samples, the mean weight with eval integrated, and each weight of a white metal is G1(wi) <= 1
// (sampling the plain normal distribution gave weights up to G1(wo) G1(wi) (wo.h) / (wo.z h.z),
// above 1 at grazing views: the noise of rough metals seen edge-on).
TEST(BsdfGgx, VisibleNormalSamplingMatchesItsDensityAndWeighsAtMostOne) {
  for (const double alpha : {0.15, 0.4, 0.8})
    for (const double mu : {0.95, 0.5, 0.1}) {
      Bsdf b;
      b.frame = Frame::from_normal({0, 0, 1});
      b.ng = {0, 0, 1};
      b.ggx_f0 = {1, 1, 1};
      b.ggx_alpha = alpha;
      const Vec3 wo = from_cos(mu);
      Rng rng = Rng::for_sample(4, 5, 6, 7);
      // Samples counted in 8 bands of cos theta_i, against the density integrated over each
      // band (midpoint rule on a fine uniform grid of directions).
      constexpr int kBands = 8, n = 40000;
      double counted[kBands] = {}, max_weight = 0, mean = 0;
      for (int i = 0; i < n; ++i) {
        Vec2 u;
        rng.uniform2(u.x, u.y);
        BsdfSample s;
        if (!b.sample(wo, u, rng.uniform(), &s)) continue;
        counted[std::min(int(s.wi.z * kBands), kBands - 1)] += 1.0 / n;
        max_weight = std::max(max_weight, max_component(s.weight));
        mean += luminance(s.weight) / n;
        const double g1 = smith_g1(s.wi.z, alpha);
        ASSERT_NEAR(max_component(s.weight), g1, 1e-9) << "alpha " << alpha << ", mu " << mu;
      }
      double expected[kBands] = {}, integrated = 0;
      constexpr int kGrid = 400;
      for (int iz = 0; iz < kGrid; ++iz)
        for (int ip = 0; ip < kGrid; ++ip) {
          const double z = (iz + 0.5) / kGrid, phi = 2 * kPi * (ip + 0.5) / kGrid;
          const double r = std::sqrt(1 - z * z);
          const Vec3 wi{r * std::cos(phi), r * std::sin(phi), z};
          const double dw = 2 * kPi / (double(kGrid) * kGrid);
          expected[std::min(int(z * kBands), kBands - 1)] += b.pdf(wo, wi) * dw;
          integrated += luminance(b.eval(wo, wi)) * z * dw;
        }
      for (int k = 0; k < kBands; ++k)
        EXPECT_NEAR(counted[k], expected[k], 0.01 + 0.03 * expected[k])
            << "alpha " << alpha << ", mu " << mu << ", band " << k;
      EXPECT_LE(max_weight, 1 + 1e-12);
      EXPECT_NEAR(mean, integrated, 0.01 + 0.02 * integrated) << "alpha " << alpha << ", mu " << mu;
    }
}

// A coat of weight 1 over black: a GGX layer with Schlick's F0 = 0.04 reflecting 4 % head-on
// into its specular peak (rough 0.3: albedo 0.04..0.05 with the Fresnel's rise off-centre).
TEST(BsdfLayers, CoatOverBlackIsA4PercentDielectric) {
  const Bsdf b = layered({0, 0, 0}, 1, 0.3, {0, 0, 0}, 0);
  const Albedo a = albedo(b, from_cos(1), 100000);
  EXPECT_NEAR(a.integrated, 0.042, 0.004);
  EXPECT_NEAR(a.sampled, a.integrated, 0.003);
  // Half the coat: half the reflection, and the base loses what the coat takes.
  Bsdf white = layered({1, 1, 1}, 1, 0.3, {0, 0, 0}, 0);
  const double under = white.under_layers(from_cos(1));
  EXPECT_NEAR(under, 0.96, 1e-12);
}

// sheen_albedo's table against an independent Monte Carlo integral of the sheen lobe alone (a
// sheen over a black base: the BSDF is the sheen).
TEST(BsdfLayers, SheenAlbedoTableMatchesTheLobesIntegral) {
  for (double r : {0.3, 0.5, 1.0})
    for (double mu : {0.95, 0.6, 0.25}) {
      const Bsdf b = layered({0, 0, 0}, 0, 0, {1, 1, 1}, r);
      const Albedo a = albedo(b, from_cos(mu), 100000);
      EXPECT_NEAR(sheen_albedo(mu, r), a.integrated, 0.01 + 0.03 * a.integrated)
          << "roughness " << r << ", cos theta_o " << mu;
    }
}

}  // namespace
}  // namespace anamorph
