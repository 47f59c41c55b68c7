// Integrators against analytic values: the furnace, Whitted mirror / glass / diffuse by hand.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <thread>

#include <filesystem>

#include "io/image_io.h"
#include "render_util.h"

namespace anamorph {

namespace {
// A camera straight at the origin from +z, one pixel at its exact center.
const std::string kOnePixel =
    "[image]\nwidth = 1\nheight = 1\n[render]\nsampler = \"center\"\n"
    "[camera]\nlook_from = [0, 0, 5]\nlook_at = [0, 0, 0]\nfov = 10\n";
}  // namespace

TEST(Furnace, DiffuseSphereUnderUniformSkyReflectsItsAlbedo) {
  // A convex diffuse object under radiance 1 everywhere: every path leaves after one bounce,
  // so the exact pixel value is the albedo.
  const std::string scene =
      "[image]\nwidth = 8\nheight = 8\n[render]\nintegrator = \"path\"\nspp = 64\nmax_depth = 8\n"
      "[camera]\nlook_from = [0, 0, 4]\nlook_at = [0, 0, 0]\nfov = 8\n"
      "[[material]]\nname = \"white\"\ncolor = 0.8\n"
      "[[object]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"white\"\n"
      "[environment]\ncolor = 1\n";
  const auto r = test::render_text(scene);
  double sum = 0;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) sum += luminance(r.film->pixel(x, y));
  EXPECT_NEAR(sum / 64, 0.8, 0.01) << "mean radiance of the furnace";
}

TEST(Furnace, ConstantSkyIsSampledAboutTheNormalWithZeroVariance) {
  // Light sampling draws the constant sky cosine-weighted about the shading normal, the same
  // density as the diffuse BSDF: with the power heuristic each technique carries weight 1/2 and
  // every sample of every pixel is exactly albedo * L, at any sample count. (Sampling the whole
  // sphere wasted half the light samples below the surface: at 4 spp the pixels were off by 0.029
  // RMS.)
  const std::string scene =
      "[image]\nwidth = 8\nheight = 8\n[render]\nintegrator = \"path\"\nspp = 4\nmax_depth = 8\n"
      "[camera]\nlook_from = [0, 0, 4]\nlook_at = [0, 0, 0]\nfov = 8\n"
      "[[material]]\nname = \"white\"\ncolor = 0.8\n"
      "[[object]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"white\"\n"
      "[environment]\ncolor = 0.5\n";
  const auto r = test::render_text(scene);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x)
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(r.film->pixel(x, y)[c], 0.4, 1e-5) << "pixel " << x << "," << y << " c" << c;
}

TEST(Furnace, MetallicRoughnessWhiteFurnaceStaysBelowOne) {
  const std::string scene =
      "[image]\nwidth = 8\nheight = 8\n[render]\nintegrator = \"path\"\nspp = 64\n"
      "[camera]\nlook_from = [0, 0, 4]\nlook_at = [0, 0, 0]\nfov = 8\n"
      "[[material]]\nname = \"m\"\ntype = \"metallic_roughness\"\ncolor = 1\nmetallic = "
      "1\nroughness = 0.5\n"
      "[[object]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"m\"\n"
      "[environment]\ncolor = 1\n";
  const auto r = test::render_text(scene);
  double sum = 0;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) sum += luminance(r.film->pixel(x, y));
  // A single-scattering GGX metal loses some energy (no multiple scattering): in (0.85, 1].
  EXPECT_GT(sum / 64, 0.85);
  EXPECT_LE(sum / 64, 1.01);
}

TEST(Whitted, PerfectMirrorShowsTheSky) {
  const auto r = test::render_text(kOnePixel +
                                   "[[material]]\nname = \"m\"\ncolor = 0\nreflectivity = 1\n"
                                   "[[object]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"m\"\n"
                                   "[environment]\ncolor = [0.2, 0.4, 0.6]\n");
  // The film sums in float: its values are the radiance rounded to 24 bits.
  const Color c = r.film->pixel(0, 0);
  EXPECT_NEAR(c.x, 0.2, 1e-7);
  EXPECT_NEAR(c.y, 0.4, 1e-7);
  EXPECT_NEAR(c.z, 0.6, 1e-7);
}

TEST(Whitted, GlassSphereAtNormalIncidence) {
  // Along the axis every interface has F = ((1.5 - 1) / 2.5)^2 = 0.04.
  // max_depth 1: only the front reflection reaches the sky: 0.04 c.
  // max_depth 2: plus the ray through both interfaces: (0.96 / 1.5^2) * (0.96 * 1.5^2) c.
  const std::string scene = kOnePixel +
                            "[[material]]\nname = \"g\"\ncolor = 1\ntransmission = 1\nior = 1.5\n"
                            "[[object]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"g\"\n"
                            "[environment]\ncolor = 0.5\n";
  const double F = 0.04;
  const auto r1 = test::render_text(scene, {"render.max_depth=1"});
  EXPECT_NEAR(r1.film->pixel(0, 0).x, F * 0.5, 1e-7);  // (float film)
  const auto r2 = test::render_text(scene, {"render.max_depth=2"});
  EXPECT_NEAR(r2.film->pixel(0, 0).x, (F + (1 - F) * (1 - F)) * 0.5, 1e-7);
}

// Glass inside a closed mirror, traced to depth 1000: without a cut-off the tree has 2^1000
// branches (the probe's scene ignored SIGTERM for ten minutes). Each branch's weight is at most
// its parent's (mirror reflectivity <= 1; transmission times F and times 1 - F sum to at most 1),
// so at most 1 / bailout branches per depth survive: at most (depth + 1) / bailout traced rays.
const std::string kGlassInMirror =
    "[image]\nwidth = 1\nheight = 1\n[render]\nsampler = \"center\"\nmax_depth = 1000\n"
    "[camera]\nlook_from = [0, 0, 0]\nlook_at = [0, 0.1, -1]\nfov = 10\n"
    "[[material]]\nname = \"g\"\ncolor = 0\ntransmission = 1\nior = 1.5\n"
    "[[material]]\nname = \"m\"\ncolor = 0\nreflectivity = 0.99\nemission = 0.01\n"
    "[[object]]\ntype = \"sphere\"\nradius = 0.5\ncenter = [0, 0, -2]\nmaterial = \"g\"\n"
    "[[object]]\ntype = \"sphere\"\nradius = 5\nmaterial = \"m\"\n";

TEST(Whitted, BailoutBoundsTheRayTreeAtAnyDepth) {
  for (const double bailout : {1.0 / 255, 0.01, 0.1}) {
    const auto r = test::render_text(kGlassInMirror, {fmt::format("render.bailout={}", bailout)});
    const double bound = 1001 / bailout;
    EXPECT_LE(double(r.stats.rays), bound) << "bailout " << bailout;
    EXPECT_GT(r.stats.rays, 10u) << "the tree is traced past the first hits";
    EXPECT_TRUE(is_finite(r.film->pixel(0, 0)));
  }
  // Cut branches carry light that is never negative: a smaller cut-off traces more rays and
  // finds more light, converging as it shrinks.
  double last_L = 0;
  uint64_t last_rays = 0;
  for (const double bailout : {0.1, 0.01, 1.0 / 255, 1e-4, 1e-6}) {
    const auto r = test::render_text(
        kGlassInMirror, {fmt::format("render.bailout={}", bailout), "render.max_depth=30"});
    const double L = r.film->pixel(0, 0).x;
    EXPECT_GE(L, last_L) << "bailout " << bailout;
    EXPECT_GE(r.stats.rays, last_rays) << "bailout " << bailout;
    if (bailout == 1e-6) {
      EXPECT_LT(L - last_L, 0.01 * L) << "within 1% by bailout 1e-4";
    }
    last_L = L, last_rays = r.stats.rays;
  }
}

TEST(Whitted, CancelStopsInsideTheRayTree) {
  // bailout 0 and depth 1000: the one pixel's tree has about 2^1000 branches, so this render
  // only ends (and the test only passes) if the flag, set while the pixel is being traced,
  // reaches the recursion.
  const Scene scene = load_scene_from_string(kGlassInMirror, "t.toml", {"render.bailout=0"});
  const Renderer renderer(scene);
  Film film(1, 1, {});
  std::atomic<bool> cancel{false};
  RenderOptions opt;
  opt.cancel = &cancel;
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    cancel = true;
  });
  const RenderStats st = renderer.render(film, opt);
  stopper.join();
  EXPECT_TRUE(st.cancelled);
}

TEST(Whitted, DiffuseUnderPointLight) {
  // L = albedo / pi * I / h^2 at normal incidence, seen head on.
  const std::string scene =
      "[image]\nwidth = 1\nheight = 1\n[render]\nsampler = \"center\"\n"
      "[camera]\nlook_from = [0, 5, 0]\nlook_at = [0, 0, 0]\nup = [0, 0, -1]\nfov = 10\n"
      "[[material]]\nname = \"d\"\ncolor = 0.5\n"
      "[[object]]\ntype = \"plane\"\nmaterial = \"d\"\n"
      "[[light]]\ntype = \"point\"\nposition = [0, 2, 0]\nintensity = 8\n";
  const auto r = test::render_text(scene);
  EXPECT_NEAR(r.film->pixel(0, 0).x, 0.5 / kPi * 8 / 4, 1e-5);
}

TEST(Whitted, ShadowBlocksTheLight) {
  const std::string scene =
      "[image]\nwidth = 1\nheight = 1\n[render]\nsampler = \"center\"\n"
      "[camera]\nlook_from = [0, 5, 0]\nlook_at = [0, 0, 0]\nup = [0, 0, -1]\nfov = 1\n"
      "[[object]]\ntype = \"plane\"\n"
      "[[object]]\ntype = \"disk\"\ncenter = [0, 1, 0]\nradius = 0.1\nnormal = [0, 1, 0]\n"
      "[[light]]\ntype = \"point\"\nposition = [0, 2, 0]\nintensity = 8\n";
  // The camera sees the disk at y = 1 (it is between), so move it: look past the disk.
  const auto lit = test::render_text(scene, {"object.1.center=[5, 1, 0]"});
  const auto shadowed =
      test::render_text(scene, {"camera.look_from=[0.3, 5, 0]", "camera.look_at=[0.3, 0, 0]",
                                "object.1.center=[0.15, 1, 0]"});
  EXPECT_GT(lit.film->pixel(0, 0).x, 0.1);
  EXPECT_EQ(shadowed.film->pixel(0, 0).x, 0.0);
}

TEST(Whitted, ShadowRaysPassTransparentSurfacesScaledByTheirTransmission) {
  // A sphere on the segment from the point light to the seen floor point: the shadow ray crosses
  // its surface twice, so a transmission t lets t^2 of the light through (Whitted 1980, POV-Ray).
  const std::string scene =
      "[image]\nwidth = 1\nheight = 1\n[render]\nsampler = \"center\"\n"
      "[camera]\nlook_from = [2, 5, 0]\nlook_at = [2, 0, 0]\nup = [0, 0, -1]\nfov = 1\n"
      "[[material]]\nname = \"floor\"\ncolor = 0.5\n"
      "[[material]]\nname = \"glass\"\ntransmission = 0.5\n"
      "[[object]]\ntype = \"plane\"\nmaterial = \"floor\"\n"
      "[[object]]\ntype = \"sphere\"\ncenter = [1, 1, 0]\nradius = 0.2\nmaterial = \"glass\"\n"
      "[[light]]\ntype = \"point\"\nposition = [0, 2, 0]\nintensity = 8\n";
  const double lit = test::render_text(scene, {"object.1.center=[-5, 1, 0]"}).film->pixel(0, 0).x;
  ASSERT_GT(lit, 0.01);
  for (const double t : {0.0, 0.5, 1.0}) {
    const auto r = test::render_text(scene, {"material.1.transmission=" + std::to_string(t)});
    EXPECT_NEAR(r.film->pixel(0, 0).x / lit, t * t, 1e-9) << "transmission " << t;
  }
  // Two such spheres on the segment: t^4.
  const auto two =
      test::render_text(scene +
                        "[[object]]\ntype = \"sphere\"\ncenter = [1.5, 0.5, 0]\nradius = 0.1\n"
                        "material = \"glass\"\n");
  EXPECT_NEAR(two.film->pixel(0, 0).x / lit, 0.0625, 1e-9);
}

TEST(Aov, DepthIsDistanceAlongTheRay) {
  const auto r = test::render_text(
      "[image]\nwidth = 3\nheight = 3\n[render]\nintegrator = \"depth\"\nsampler = \"center\"\n"
      "[camera]\nlook_from = [0, 0, 5]\nlook_at = [0, 0, 0]\nfov = 60\n"
      "[[object]]\ntype = \"plane\"\nnormal = [0, 0, 1]\n",
      {}, 0, {Aov::Depth, Aov::Normal});
  // Center pixel: 5. Corner pixel: 5 / cos(angle to the axis).
  EXPECT_NEAR(r.film->pixel(1, 1).x, 5, 1e-5);
  const auto ray = r.scene.camera->generate({{0.5 / 3, 0.5 / 3}});
  EXPECT_NEAR(r.film->pixel(0, 0).x, 5 / -ray->dir.z, 1e-5);
  const OutputImage out = r.film->output();
  ASSERT_EQ(out.layers.size(), 3u);
  EXPECT_EQ(out.layers[1].name, "depth");
  EXPECT_NEAR(out.layers[2].data[4 * 3 + 2], 1.0, 1e-9) << "normal faces the camera";
}

TEST(Film, NoRaySamplesAreTransparent) {
  // A fisheye-like composition that yields no ray: a zero direction.
  const auto r = test::render_text(
      "[image]\nwidth = 2\nheight = 2\n"
      "[camera]\norg = { type = \"plane\" }\ndir = { type = \"from_surface\", surface = { type = "
      "\"point\" } }\n");
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 2; ++x) EXPECT_EQ(r.film->alpha(x, y), 0.0);
}

}  // namespace anamorph

namespace anamorph {

namespace {
// A diffuse floor seen straight down at one point; a sphere light of radiance 10, radius 0.5,
// centred 3 above it. Irradiance pi L (r/d)^2, so the floor's radiance is albedo L (r/d)^2.
const std::string kSphereLight =
    "[image]\nwidth = 2\nheight = 2\n[render]\nspp = 256\n"
    "[camera]\nlook_from = [0, 1, 0]\nlook_at = [0, 0, 0]\nup = [0, 0, -1]\nfov = 0.01\n"
    "[[material]]\nname = \"d\"\ncolor = 0.5\n"
    "[[object]]\ntype = \"plane\"\nmaterial = \"d\"\n"
    "[[light]]\ntype = \"sphere\"\ncenter = [0, 3, 0]\nradius = 0.5\nradiance = 10\n";
double mean_red(const test::Rendered& r) {
  double s = 0;
  for (int y = 0; y < r.film->height(); ++y)
    for (int x = 0; x < r.film->width(); ++x) s += r.film->pixel(x, y).x;
  return s / (r.film->width() * r.film->height());
}
}  // namespace

TEST(AreaLights, SphereLightIrradianceWhittedAndPath) {
  const double want = 0.5 * 10 * (0.5 / 3) * (0.5 / 3);
  EXPECT_NEAR(mean_red(test::render_text(kSphereLight, {"render.integrator=whitted"})), want,
              0.01 * want);
  EXPECT_NEAR(
      mean_red(test::render_text(kSphereLight, {"render.integrator=path", "render.max_depth=1"})),
      want, 0.01 * want);
}

TEST(AreaLights, QuadLightMatchesTheSphereOfEqualSolidAngleRoughly) {
  // A small quad light of area A at height h: irradiance ~ L A / h^2 at the point below it.
  const std::string scene =
      "[image]\nwidth = 2\nheight = 2\n[render]\nspp = 256\nintegrator = \"path\"\nmax_depth = 1\n"
      "[camera]\nlook_from = [0, 1, 0]\nlook_at = [0, 0, 0]\nup = [0, 0, -1]\nfov = 0.01\n"
      "[[material]]\nname = \"d\"\ncolor = 0.5\n"
      "[[object]]\ntype = \"plane\"\nmaterial = \"d\"\n"
      "[[light]]\ntype = \"quad\"\ncorner = [-0.05, 3, -0.05]\nedge_u = [0.1, 0, 0]\nedge_v = [0, "
      "0, 0.1]\n"
      "radiance = 100\n";
  const double want = 0.5 / kPi * 100 * 0.01 / 9;
  EXPECT_NEAR(mean_red(test::render_text(scene)), want, 0.01 * want);
}

TEST(Environment, ImageFurnaceIsImportanceSampledWithoutBias) {
  // A constant-valued environment image must give the same furnace answer as a constant colour.
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "anamorph_env_test";
  fs::create_directories(dir);
  OutputImage img;
  img.width = 16;
  img.height = 8;
  ImageLayer l;
  l.channels = {"R", "G", "B", "A"};
  for (int i = 0; i < 16 * 8; ++i) l.data.insert(l.data.end(), {1.f, 1.f, 1.f, 1.f});
  // A bright band near the horizon makes the importance sampling non-trivial.
  for (int x = 0; x < 16; ++x)
    for (int c = 0; c < 3; ++c) l.data[size_t((4 * 16 + x) * 4 + c)] = 5.f;
  img.layers.push_back(l);
  write_exr(dir / "env.exr", img);
  const std::string scene =
      "[image]\nwidth = 4\nheight = 4\n[render]\nintegrator = \"path\"\nspp = 256\n"
      "[camera]\nlook_from = [0, 0, 4]\nlook_at = [0, 0, 0]\nfov = 5\n"
      "[[material]]\nname = \"w\"\ncolor = 0.8\n"
      "[[object]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"w\"\n"
      "[environment]\nfile = \"" +
      (dir / "env.exr").string() + "\"\n";
  const auto r = test::render_text(scene);
  // Reference: the same scene lit by a brute-force estimate is hard to state analytically, so
  // check the invariant instead: doubling `strength` doubles the image (linearity) and the
  // value lies between the darkest and brightest sky times the albedo.
  const double v = mean_red(r);
  EXPECT_GT(v, 0.8 * 1.0);
  EXPECT_LT(v, 0.8 * 5.0);
  const auto r2 = test::render_text(scene, {"environment.strength=2"});
  EXPECT_NEAR(mean_red(r2), 2 * v, 1e-9 * v);
  fs::remove_all(dir);
}

}  // namespace anamorph
