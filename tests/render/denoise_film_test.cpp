// A render denoised (render/denoise_film.h): closer to a high-spp reference than the noisy
// render it came from, its two halves merged back into the same film a plain render gives
// (alpha, AOV layers, sample counts), the no-ray region of a fisheye left without a ray, and
// the same bits for any thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "render/denoise_film.h"
#include "render/rim_coverage.h"
#include "render_util.h"
#include "test_util.h"

namespace anamorph {

namespace {

// A small box: a checker floor (texture edges), a sphere (geometry edges) and a ceiling light;
// path traced, so 16 spp is noisy.
// (Appended piece by piece: GCC 12 at -O3 warns falsely, -Warray-bounds, on a chain of
// std::string operator+ here.)
std::string box(int side, const std::string& camera) {
  std::string s = "[image]\nwidth = ";
  s += std::to_string(side);
  s += "\nheight = ";
  s += std::to_string(side);
  s += "\n[render]\nintegrator = \"path\"\nantialias = \"uniform\"\nspp = 16\nmax_depth = 4\n"
       "tile_size = 16\n[camera]\n";
  s += camera;
  return s +
         "[[material]]\nname = \"c\"\ncolor = { type = \"checker\", scale = 0.6, "
         "color_a = [0.8, 0.8, 0.8], color_b = [0.2, 0.3, 0.6] }\n"
         "[[material]]\nname = \"w\"\ncolor = [0.7, 0.5, 0.3]\n"
         "[[object]]\ntype = \"plane\"\nmaterial = \"c\"\n"
         "[[object]]\ntype = \"sphere\"\ncenter = [0, 0.6, 0]\nradius = 0.6\nmaterial = \"w\"\n"
         "[[light]]\ntype = \"quad\"\ncorner = [-1, 3, -1]\nedge_u = [2, 0, 0]\nedge_v = [0, 0, "
         "2]\nradiance = 4\n[environment]\ncolor = [0.3, 0.35, 0.4]\n";
}
const std::string kPerspective = "look_from = [0, 1.6, 4]\nlook_at = [0, 0.5, 0]\nfov = 45\n";
const std::string kFisheye =
    "preset = \"fisheye\"\nfov = 180\nlook_from = [0, 1.5, 3]\nlook_at = [0, 0.3, 0]\n";

struct Denoised {
  Scene scene;
  std::unique_ptr<Film> film;
  DenoisedRender r;
};

Denoised render_denoised_text(const std::string& toml, const std::vector<std::string>& over,
                              int threads = 2) {
  Denoised d{load_scene_from_string(toml, "test.toml", over), nullptr, {}};
  const RenderSettings& rs = d.scene.render;
  d.film = std::make_unique<Film>(rs.width, rs.height, with_denoise_aovs({}), rs.tile_size);
  RenderOptions opt;
  opt.threads = threads;
  d.r = render_denoised(Renderer(d.scene), rs, *d.film, opt);
  return d;
}

// RMSE of the RGB of two beauty layers (RGBA) over the pixels covered in both.
double rmse(const std::vector<float>& a, const std::vector<float>& b) {
  double sum = 0;
  size_t n = 0;
  for (size_t i = 0; i + 3 < a.size(); i += 4) {
    if (a[i + 3] <= 0 || b[i + 3] <= 0) continue;
    for (int c = 0; c < 3; ++c) sum += std::pow(double(a[i + c]) - b[i + c], 2);
    n += 3;
  }
  return n ? std::sqrt(sum / double(n)) : 0;
}

std::vector<float> beauty(const Film& f) { return f.output().layers[0].data; }

}  // namespace

// Measured (48 x 48, 1024-spp reference; release build): RMSE 4 spp 0.0445, 4 spp denoised
// 0.0161 (0.0190 with the features from the colour's own samples), 256 spp 0.0034 (printed; at 16
// spp 0.0178 -> 0.0121 since the light tree's pick made the noisy frame 4.7x better). The test asks
// the denoised frame for 0.6 of the error of the frame it came from.
TEST(DenoiseFilm, CloserToTheReferenceThanTheNoisyRender) {
  const int side = 48;  // (at 24 x 24 the denoiser's windows cover the image: 0.87x, not 0.43x)
  const std::string scene = box(side, kPerspective);
  const std::string ref_spp = "render.spp=" + std::to_string(test::kSanitized ? 256 : 1024);
  const auto ref = test::render_text(scene, {ref_spp});
  const auto noisy = test::render_text(scene, {"render.spp=4"});
  const Denoised den = render_denoised_text(scene, {"render.spp=4"});
  ASSERT_TRUE(den.r.denoised);
  const double before = rmse(beauty(*noisy.film), beauty(*ref.film));
  const double after = rmse(beauty(*den.film), beauty(*ref.film));
  if (!test::kSanitized) {
    const auto spp256 = test::render_text(scene, {"render.spp=256"});
    std::printf("RMSE vs 1024 spp: 4 spp %.4f, 4 spp denoised %.4f, 256 spp %.4f\n", before, after,
                rmse(beauty(*spp256.film), beauty(*ref.film)));
  }
  EXPECT_LT(after, 0.6 * before) << "RMSE 4 spp " << before << ", denoised " << after;
}

// The halves merged are the film a plain render of all the samples gives: the same sample
// counts and AOV layers (to float rounding: the sums are added in another order).
TEST(DenoiseFilm, HalvesMergeIntoThePlainRendersFilm) {
  const std::string scene = box(24, kFisheye);
  const auto plain = test::render_text(scene, {}, 2, with_denoise_aovs({Aov::Spp}));
  const RenderSettings& rs = plain.scene.render;
  Film film(rs.width, rs.height, with_denoise_aovs({Aov::Spp}), rs.tile_size);
  RenderOptions opt;
  opt.threads = 2;
  ASSERT_TRUE(render_denoised(Renderer(plain.scene), rs, film, opt).denoised);
  // The denoiser's textures are filtered over the finest footprint (RenderOptions).
  Film whole(rs.width, rs.height, with_denoise_aovs({Aov::Spp}), rs.tile_size);
  opt.aovs = whole.aovs();
  opt.finest_footprint = true;
  Renderer(plain.scene).render(whole, opt);
  const OutputImage a = whole.output(), b = film.output();
  ASSERT_EQ(a.layers.size(), b.layers.size());
  // Layer 0, the beauty: its colour is the denoised one, and its alpha at the fisheye's rim the
  // camera's (RimCoverageIsTheCamerasNotTheSamples).
  for (size_t l = 1; l < a.layers.size(); ++l) {
    const std::vector<float>&u = a.layers[l].data, &v = b.layers[l].data;
    ASSERT_EQ(u.size(), v.size());
    for (size_t i = 0; i < u.size(); ++i) {
      if (std::isinf(u[i]) && u[i] == v[i]) continue;
      ASSERT_NEAR(u[i], v[i], 1e-5 * std::max(1.0f, std::fabs(u[i])))
          << "layer '" << a.layers[l].name << "' float " << i;
    }
  }
}

// Under a 180-degree fisheye the corners have no ray: they stay transparent black, every covered
// pixel stays covered, no colour is invented or lost at the
// rim (the mean over the covered pixels within 5% of the noisy render's), and any thread count
// gives the same bits.
TEST(DenoiseFilm, FisheyeNoRayRegionStaysNoRay) {
  const std::string scene = box(32, kFisheye);
  const auto noisy = test::render_text(scene);
  const Denoised one = render_denoised_text(scene, {}, 1), two = render_denoised_text(scene, {}, 2);
  ASSERT_TRUE(one.r.denoised);
  const std::vector<float> n = beauty(*noisy.film), d = beauty(*one.film), d2 = beauty(*two.film);
  ASSERT_EQ(n.size(), d.size());
  size_t no_ray = 0;
  double mean_n = 0, mean_d = 0;
  for (size_t i = 0; i < n.size(); i += 4) {
    EXPECT_EQ(n[i + 3] > 0, d[i + 3] > 0) << "coverage at pixel " << i / 4;
    if (n[i + 3] == 0) {
      ++no_ray;
      EXPECT_TRUE(d[i] == 0 && d[i + 1] == 0 && d[i + 2] == 0) << "no-ray pixel " << i / 4;
      continue;
    }
    for (int c = 0; c < 3; ++c) mean_n += n[i + c], mean_d += d[i + c];
  }
  EXPECT_GT(no_ray, n.size() / 4 / 8) << "the fisheye's corners should have no ray";
  EXPECT_NEAR(mean_d / mean_n, 1.0, 0.05) << "mean over covered pixels";
  EXPECT_EQ(0, std::memcmp(d.data(), d2.data(), d.size() * sizeof(float)))
      << "1 vs 2 threads differ";
}

// A denoised rim pixel's alpha is the camera's coverage of it (render/rim_coverage.h), not its
// 16 samples': the covered area of a 180-degree fisheye's image, the sum of the alphas, is the
// inscribed circle's, pi (W/2)^2, where the noisy render's is off by its sampling error.
TEST(DenoiseFilm, RimCoverageIsTheCamerasNotTheSamples) {
  const int side = 32;
  const std::string scene = box(side, kFisheye);
  const auto noisy = test::render_text(scene);
  const Denoised d = render_denoised_text(scene, {});
  ASSERT_TRUE(d.r.denoised);
  const std::vector<float> n = beauty(*noisy.film), b = beauty(*d.film);
  double area_n = 0, area_d = 0;
  for (size_t i = 3; i < n.size(); i += 4) area_n += n[i], area_d += b[i];
  const double circle = kPi * (side / 2.0) * (side / 2.0);
  EXPECT_NEAR(area_d, circle, 0.002 * circle) << "noisy render's area " << area_n;
  // Each rim pixel's alpha, against the camera's coverage at 64 x 64 positions.
  std::vector<uint8_t> rim(size_t(side) * side);
  for (size_t i = 0; i < rim.size(); ++i) rim[i] = n[4 * i + 3] > 0 && n[4 * i + 3] < 1;
  const std::vector<float> fine =
      rim_coverage(*d.scene.camera, d.scene.render, side, side, rim, 64);
  double worst = 0;
  for (size_t i = 0; i < rim.size(); ++i)
    if (rim[i]) worst = std::max(worst, std::fabs(double(fine[i]) - b[4 * i + 3]));
  EXPECT_LT(worst, 0.02) << "rim alpha against the camera's coverage at 64 x 64";
}

TEST(DenoiseFilm, RefusesWhatItCannotDenoise) {
  RenderSettings rs;
  rs.antialias = Antialias::Uniform;
  rs.spp = 1;
  EXPECT_TRUE(denoise_unsupported(rs));
  rs.spp = 4;
  EXPECT_FALSE(denoise_unsupported(rs));
  rs.time_limit = 10;
  EXPECT_TRUE(denoise_unsupported(rs));
  rs.time_limit = 0;
  rs.antialias = Antialias::Pixel;
  EXPECT_TRUE(denoise_unsupported(rs));
}

// The features' samples (denoise_feature_spp): 8 times the colour's, at most 256, never fewer
// than the colour's.
TEST(DenoiseFilm, FeatureSamplesOutnumberTheColours) {
  const std::pair<int, uint32_t> cases[] = {{2, 16},   {16, 128},  {32, 256},
                                            {64, 256}, {256, 256}, {1024, 1024}};
  for (const auto& [spp, want] : cases) EXPECT_EQ(want, denoise_feature_spp(spp)) << spp << " spp";
}

// The feature pass renders with settings of its own (RenderOptions::settings: the albedo view at
// more samples) through the path-traced scene's renderer: the same bits as a renderer of the
// scene loaded with those settings.
TEST(DenoiseFilm, SettingsOverrideEqualsTheSceneWithThem) {
  const std::string scene = box(24, kPerspective);
  const Scene path = load_scene_from_string(scene, "test.toml", {});
  const Scene albedo =
      load_scene_from_string(scene, "test.toml", {"render.integrator=albedo", "render.spp=8"});
  RenderSettings rs = path.render;
  rs.view = View::Albedo;
  rs.spp = 8;
  const std::vector<Aov> aovs = with_denoise_aovs({});
  Film over(24, 24, aovs, 16), plain(24, 24, aovs, 16);
  RenderOptions opt;
  opt.threads = 2;
  opt.aovs = aovs;
  opt.progressive = false;
  Renderer(albedo).render(plain, opt);
  opt.settings = &rs;
  Renderer(path).render(over, opt);
  const OutputImage a = over.output(), b = plain.output();
  ASSERT_EQ(a.layers.size(), b.layers.size());
  for (size_t l = 0; l < a.layers.size(); ++l) {
    ASSERT_EQ(a.layers[l].data.size(), b.layers[l].data.size());
    EXPECT_EQ(0, std::memcmp(a.layers[l].data.data(), b.layers[l].data.data(),
                             a.layers[l].data.size() * sizeof(float)))
        << "layer " << l << " differs";
  }
}

}  // namespace anamorph
