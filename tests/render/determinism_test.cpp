// Images are bit-identical whatever the thread count or tile size.
#include <gtest/gtest.h>

#include <cstring>

#include "render_util.h"

namespace anamorph {

namespace {
const std::string kScene =
    "[image]\nwidth = 67\nheight = 41\n[render]\nintegrator = \"path\"\nspp = 3\nmax_depth = "
    "4\ntile_size = 8\n"
    "[camera]\nlook_from = [0, 1.5, 5]\nlook_at = [0, 0.5, 0]\nfov = 50\naperture_radius = "
    "0.05\nfocus_distance = 5\n"
    "[[material]]\nname = \"c\"\ncolor = { type = \"checker\", scale = 0.5 }\n"
    "[[material]]\nname = \"g\"\ncolor = 1\ntransmission = 1\n"
    "[[object]]\ntype = \"plane\"\nmaterial = \"c\"\n"
    "[[object]]\ntype = \"sphere\"\ncenter = [0, 0.7, 0]\nradius = 0.7\nmaterial = \"g\"\n"
    "[[light]]\ntype = \"quad\"\ncorner = [-1, 3, -1]\nedge_u = [2, 0, 0]\nedge_v = [0, 0, "
    "2]\nradiance = 5\n"
    "[environment]\ncolor = [0.1, 0.2, 0.3]\n";

std::vector<float> pixels(const test::Rendered& r) { return r.film->output().layers[0].data; }

void expect_identical(const std::vector<float>& a, const std::vector<float>& b, const char* what) {
  ASSERT_EQ(a.size(), b.size());
  size_t diff = 0, first = 0;
  for (size_t i = 0; i < a.size(); ++i)
    if (std::memcmp(&a[i], &b[i], sizeof(float)) != 0 && diff++ == 0) first = i;
  EXPECT_EQ(diff, 0u) << what << ": " << diff << " values differ, first at float " << first << ": "
                      << a[first] << " vs " << b[first];
}
}  // namespace

TEST(Determinism, OneThreadEqualsAllThreads) {
  const auto one = test::render_text(kScene, {}, 1);
  const auto many = test::render_text(kScene, {}, 4);
  expect_identical(pixels(one), pixels(many), "1 vs 4 threads");
}

TEST(Determinism, TileSizeDoesNotChangeTheImage) {
  const auto small = test::render_text(kScene, {"render.tile_size=4"});
  const auto whole = test::render_text(kScene, {"render.tile_size=1024"});
  expect_identical(pixels(small), pixels(whole), "4 px tiles vs one tile");
}

TEST(Determinism, SeedChangesTheNoise) {
  const auto a = test::render_text(kScene, {"render.seed=1"});
  const auto b = test::render_text(kScene, {"render.seed=2"});
  EXPECT_NE(pixels(a), pixels(b));
}

TEST(Determinism, WhittedAlsoDeterministic) {
  const auto one = test::render_text(kScene, {"render.integrator=whitted"}, 1);
  const auto many = test::render_text(kScene, {"render.integrator=whitted"}, 3);
  expect_identical(pixels(one), pixels(many), "whitted 1 vs 3 threads");
}

// A render's first samples overwrite the film (how `anamorph bench` reuses one film without
// clearing it): rendering into a film that holds another image gives the same bits as a fresh
// film, beauty and AOVs alike.
TEST(Determinism, RenderingOverAnOldImageEqualsAFreshFilm) {
  const std::vector<Aov> aovs = {Aov::Albedo, Aov::Depth, Aov::Id, Aov::Spp};
  const auto fresh = test::render_text(kScene, {}, 2, aovs);
  const auto other = test::render_text(kScene, {"render.seed=9", "render.spp=5"}, 2, aovs);
  Film& reused = *other.film;
  RenderOptions opt;
  opt.threads = 2;
  opt.aovs = aovs;
  Renderer(fresh.scene).render(reused, opt);
  const OutputImage a = fresh.film->output(), b = reused.output();
  ASSERT_EQ(a.layers.size(), b.layers.size());
  for (size_t i = 0; i < a.layers.size(); ++i)
    expect_identical(a.layers[i].data, b.layers[i].data, "fresh film vs film with an old image");
}

}  // namespace anamorph
