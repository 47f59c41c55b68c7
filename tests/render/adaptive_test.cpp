// Adaptive antialiasing: where samples go, and that adaptivity keeps images deterministic.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>

#include "render/adaptive.h"
#include "render_util.h"
#include "scene/toml_reader.h"

namespace anamorph {

namespace {

// Whitted, adaptive: a white sphere in front of a black sky.
const std::string kEdge =
    "[image]\nwidth = 40\nheight = 30\n[render]\nintegrator = \"whitted\"\nantialias = "
    "\"adaptive\"\n"
    "aa_depth = 3\ntile_size = 8\n"
    "[camera]\nlook_from = [0, 0, 5]\nlook_at = [0, 0, 0]\nfov = 40\n"
    "[[material]]\nname = \"e\"\ncolor = 0\nemission = 1\n"
    "[[object]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"e\"\n";

uint32_t spp(const test::Rendered& r, int x, int y) { return r.film->samples(x, y); }

// Adaptive sampling of a constant sky through `camera` (TOML lines of [camera]): equal image
// content everywhere, so only the camera's stretch can add samples.
std::string sky(int width, int height, int depth, const std::string& camera) {
  return "[image]\nwidth = " + std::to_string(width) + "\nheight = " + std::to_string(height) +
         "\n[render]\nantialias = \"adaptive\"\naa_depth = " + std::to_string(depth) +
         "\n[camera]\n" + camera + "\n[environment]\ncolor = 0.5\n";
}

}  // namespace

TEST(Adaptive, FlatRegionGetsOnlyItsCornersAndEdgesGetMore) {
  const auto r = test::render_text(kEdge);
  EXPECT_EQ(spp(r, 0, 0), 4u) << "flat black corner of the image";
  EXPECT_EQ(spp(r, 20, 15), 4u) << "flat white middle of the sphere";
  // Along the middle row, some pixel crosses the silhouette and is refined.
  uint32_t most = 0;
  for (int x = 0; x < 40; ++x) most = std::max(most, spp(r, x, 15));
  EXPECT_GT(most, 4u);
  // The silhouette pixel's value lies strictly between black and white: antialiased.
  int partial = 0;
  for (int x = 0; x < 40; ++x) {
    const double v = r.film->pixel(x, 15).x;
    partial += v > 0.02 && v < 0.98;
  }
  EXPECT_GE(partial, 2);
}

TEST(Adaptive, NoSeamsAtTileBordersAndThreadIndependent) {
  const auto small = test::render_text(kEdge, {"render.tile_size=4"}, 1);
  const auto whole = test::render_text(kEdge, {"render.tile_size=64"}, 2);
  const auto a = small.film->output().layers[0].data, b = whole.film->output().layers[0].data;
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(float)))
      << "one tile vs many tiles (and 1 vs 2 threads) must give identical bits";
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x)
      ASSERT_EQ(small.film->samples(x, y), whole.film->samples(x, y)) << x << "," << y;
}

TEST(Adaptive, StretchedPixelsStartSubdivided) {
  // A very wide perspective camera spreads its pixels unevenly: a center pixel covers about
  // 1/cos^3 more solid angle than an edge pixel, so the distortion map splits it from the start.
  const auto r =
      test::render_text(sky(64, 64, 3, "look_from = [0, 0, 0]\nlook_at = [0, 0, -1]\nfov = 170"));
  EXPECT_GT(spp(r, 32, 32), spp(r, 0, 32))
      << "the center of a 170 degree perspective covers more solid angle";
  EXPECT_EQ(spp(r, 0, 32), 4u);
}

TEST(Adaptive, NoiseDrivenPathStopsFlatPixelsEarly) {
  const std::string scene =
      "[image]\nwidth = 32\nheight = 16\n[render]\nintegrator = \"path\"\nantialias = "
      "\"adaptive\"\n"
      "min_spp = 8\nmax_spp = 256\nnoise_threshold = 0.002\n"
      "[camera]\nlook_from = [0, 0, 5]\nlook_at = [0, 0, 0]\nfov = 50\n"
      "[[object]]\ntype = \"box\"\ncenter = [1.5, 0, 0]\nsize = [2, 2, 2]\n"
      // (facing down, in front of the box's front face: that face was not lit by the light
      // above it; its flat sky light is sampled exactly since the light tree, at 8 spp)
      "[[light]]\ntype = \"quad\"\ncorner = [0.5, 3, 1]\nedge_u = [2, 0, 0]\nedge_v = [0, 0, "
      "2]\nradiance = 5\n"
      "[environment]\ncolor = 0.2\n";
  const auto r = test::render_text(scene, {}, 0, {Aov::Spp});
  // Left: only the constant sky (no variance) -> min_spp. Right: a box lit by an area light.
  EXPECT_EQ(spp(r, 1, 8), 8u);
  EXPECT_GT(spp(r, 24, 8), 8u);
  EXPECT_LE(spp(r, 24, 8), 256u);
  const auto again = test::render_text(scene, {}, 1, {Aov::Spp});
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 32; ++x) ASSERT_EQ(r.film->samples(x, y), again.film->samples(x, y));
}

}  // namespace anamorph

namespace anamorph {

TEST(Adaptive, FisheyeRimGetsMoreSamplesThanItsCenter) {
  // An orthographic-mapping fisheye squeezes the horizon into the rim of its image circle: rim
  // pixels cover far more of the scene. Equal content (a constant sky) everywhere.
  const auto r = test::render_text(
      sky(64, 64, 3, "preset = \"fisheye\"\nmapping = \"orthographic\"\nfov = 180"));
  const uint32_t center = r.film->samples(32, 32);
  uint32_t rim = 0;
  for (int x = 0; x < 4; ++x) rim = std::max(rim, r.film->samples(x, 32));
  EXPECT_EQ(center, 4u);
  EXPECT_GT(rim, center) << "rim pixels of an orthographic fisheye are stretched";
}

TEST(Adaptive, SeamsOfPiecewiseCamerasStartAtFullDepth) {
  // A 3x2 cubemap of 32-pixel faces: where two faces meet, neighbouring corners' rays are far from
  // where the differentials predict them, so a pixel at each seam gets every level (5 x 5 lattice
  // points at depth 2) before any contrast is seen. Equal content (a constant sky) everywhere.
  const auto r = test::render_text(sky(96, 64, 2, "preset = \"cubemap\"\nlayout = \"3x2\""));
  for (int y : {3, 20, 40, 60}) {
    for (int seam : {32, 64}) {
      uint32_t most = 0;
      for (int x = seam - 2; x < seam + 2; ++x) most = std::max(most, spp(r, x, y));
      EXPECT_EQ(most, 25u) << "vertical seam at x = " << seam << ", row " << y;
    }
    EXPECT_EQ(spp(r, 16, y), 4u) << "inside a face, row " << y;
  }
  // (Faces 2 and 5, +y above -z, meet along their common cube edge: the ray field is continuous
  // there, and that seam rightly needs nothing.)
  for (int x : {5, 50}) {
    uint32_t most = 0;
    for (int y = 30; y < 34; ++y) most = std::max(most, spp(r, x, y));
    EXPECT_EQ(most, 25u) << "horizontal seam at y = 32, column " << x;
  }
}

}  // namespace anamorph

namespace anamorph {

TEST(Adaptive, NoiseDrivenTexturesAreFilteredOverTheSamplesTaken) {
  // A finely checkered plane (cells about 1.3 pixels, rotated against the pixel grid) lit by one
  // directional light from the camera's side: the only variance inside a pixel is the texture.
  // Each sample filters the texture over its share of the pixel; noise-driven sampling must not
  // filter it over a whole pixel (render.spp is 1 there), which blurs the checker against a
  // uniform high-sample render of the same scene.
  const std::string scene =
      "[image]\nwidth = 32\nheight = 32\n[render]\nintegrator = \"path\"\nmax_depth = 1\n"
      "[camera]\nlook_from = [0, 0, 5]\nlook_at = [0, 0, 0]\nfov = 20\n"
      "[[material]]\nname = \"c\"\ncolor = { type = \"checker\", space = \"world\", scale = 0.07, "
      "color_a = 0.9, color_b = 0.1, transform = { rotate = [30, 0, 0, 1] } }\n"
      "[[object]]\ntype = \"plane\"\nnormal = [0, 0, 1]\nmaterial = \"c\"\n"
      "[[light]]\ntype = \"directional\"\ndirection = [0, 0, -1]\nirradiance = 3.14159265358979\n";
  const auto ref = test::render_text(scene, {"render.spp=256"});
  const auto uni = test::render_text(scene, {"render.spp=32"});
  const auto ada = test::render_text(scene, {"render.antialias=\"adaptive\"", "render.min_spp=4",
                                             "render.max_spp=64", "render.noise_threshold=0.1"});
  auto rmse = [&](const test::Rendered& a) {
    double e = 0;
    for (int y = 0; y < 32; ++y)
      for (int x = 0; x < 32; ++x) {
        const double d = a.film->pixel(x, y).x - ref.film->pixel(x, y).x;
        e += d * d;
      }
    return std::sqrt(e / (32 * 32));
  };
  const double spp = double(ada.stats.samples) / (32 * 32);
  const double e_ada = rmse(ada), e_uni = rmse(uni);
  // Measured: adaptive 0.027 at 32 samples/pixel, uniform 32 spp 0.026; with every sample
  // filtered over a whole pixel, adaptive was 0.12 (at 7 samples/pixel: the blur hid the noise).
  EXPECT_GT(spp, 8.0) << "the checker's pixels should take more than min_spp";
  EXPECT_LT(e_ada, 0.04) << "adaptive RMSE " << e_ada << " at " << spp
                         << " samples/pixel; uniform 32 spp: " << e_uni;
  EXPECT_LT(e_ada, 1.5 * e_uni) << "adaptive RMSE " << e_ada << " at " << spp
                                << " samples/pixel; uniform 32 spp: " << e_uni;
}

}  // namespace anamorph

namespace anamorph {

TEST(Adaptive, SchemesResolvedAtLoad) {
  // "adaptive" is the integrator's scheme: the corner lattice for whitted, per pixel for path.
  EXPECT_EQ(test::render_text(kEdge).scene.render.antialias, Antialias::Lattice);
  EXPECT_EQ(
      load_scene_from_string(kEdge, "t.toml", {"render.integrator=\"path\""}).render.antialias,
      Antialias::Pixel);
  EXPECT_EQ(load_scene_from_string(kEdge, "t.toml", {"render.antialias=\"pixel\""}).render.min_spp,
            2)
      << "whitted's per-pixel sampling starts at two samples";
  try {
    load_scene_from_string(kEdge, "t.toml",
                           {"render.integrator=\"path\"", "render.antialias=\"lattice\""});
    FAIL() << "the lattice compares single samples: path tracing must be refused";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("antialias"), std::string::npos) << e.what();
  }
}

TEST(Adaptive, PerPixelWhittedSpendsSamplesOnTheSilhouetteOnly) {
  const auto r = test::render_text(
      kEdge, {"render.antialias=\"pixel\"", "render.max_spp=64", "render.noise_threshold=0.01"});
  EXPECT_EQ(spp(r, 0, 0), 2u) << "flat black corner: min_spp";
  EXPECT_EQ(spp(r, 20, 15), 2u) << "flat white middle of the sphere: min_spp";
  uint32_t most = 0;
  int partial = 0;
  for (int x = 0; x < 40; ++x) {
    most = std::max(most, spp(r, x, 15));
    const double v = r.film->pixel(x, 15).x;
    partial += v > 0.02 && v < 0.98;
  }
  EXPECT_EQ(most, 64u) << "a silhouette pixel of the middle row should reach max_spp";
  EXPECT_GE(partial, 2) << "silhouette pixels lie between black and white";
  // Fewer samples than uniform sampling at max_spp by far: the sphere's disc and the sky are flat.
  const double per_pixel = double(r.stats.samples) / (40 * 30);
  EXPECT_LT(per_pixel, 20.0) << per_pixel << " samples/pixel";
  // Deterministic: tiles and threads do not change a bit or a sample count.
  const auto other = test::render_text(kEdge,
                                       {"render.antialias=\"pixel\"", "render.max_spp=64",
                                        "render.noise_threshold=0.01", "render.tile_size=4"},
                                       1);
  const auto a = r.film->output().layers[0].data, b = other.film->output().layers[0].data;
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(float)));
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 40; ++x) ASSERT_EQ(spp(r, x, y), spp(other, x, y)) << x << "," << y;
}

TEST(Adaptive, StopRuleFollowsItsFormula) {
  // One pixel with n samples alternating between luminance 0 and 1 (mean 1/2, sample standard
  // deviation s = sqrt(n / (4 (n - 1)))), the rest black (no variance). The pixel is done when
  // s * n^-(1/2 + n_power) <= threshold * sqrt(1/2 + 1e-4).
  const int n = 16;
  Film film(5, 5, {});
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 5; ++x)
      for (int i = 0; i < n; ++i) {
        const double l = (x == 2 && y == 2) ? (i & 1) : 0.0;
        film.add(x, y, {l, l, l}, 1, {});
      }
  const double s = std::sqrt(n / (4.0 * (n - 1))), m = std::sqrt(0.5 + 1e-4);
  for (const StopRule base : {StopRule::noisy(1), StopRule::deterministic(1)}) {
    const double at = s * std::pow(double(n), -(0.5 + base.n_power)) / m;  // threshold at the edge
    std::vector<uint8_t> active(25);
    StopRule rule = base;
    rule.threshold = at * 1.01;
    EXPECT_EQ(update_active(film, rule, &active), 0u) << "n_power " << base.n_power;
    rule.threshold = at * 0.99;
    const size_t busy = update_active(film, rule, &active);
    EXPECT_TRUE(active[12]) << "n_power " << base.n_power;
    // The neighbours follow only where the pixel is neighbour_factor times over its threshold.
    EXPECT_EQ(busy, base.neighbour_factor > 1 ? 1u : 9u) << "n_power " << base.n_power;
    rule.threshold = at / base.neighbour_factor * 0.99;
    EXPECT_EQ(update_active(film, rule, &active), 9u) << "n_power " << base.n_power;
  }
}

}  // namespace anamorph
