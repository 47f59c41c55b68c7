// Sphere lights far smaller than their distance (issue 32's second probe: form factors of a lamp
// of radius 1e-100 came out NaN). The cone a sphere subtends is computed from 1 - cos, which does
// not round to 0, so a tiny sphere light is a point light of intensity pi r^2 L in the limit, not
// a source of NaN samples; samples beyond the film's single precision are dropped and counted.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "math/sampling.h"
#include "render_util.h"

namespace anamorph {
namespace {

// A diffuse floor (reflectance 0.5) 1 below a sphere light of radius r and radiance 1 / r^2,
// seen from above: the floor under the light has radiance 0.5 / pi * E with E = pi r^2 L / d^2
// = pi, so 0.5, for any tiny r.
std::string tiny_light_scene(const std::string& r, const std::string& radiance) {
  return "[image]\nwidth = 9\nheight = 9\n[render]\nintegrator = \"path\"\nspp = 16\n"
         "max_depth = 1\n[camera]\npreset = \"orthographic\"\nlook_from = [0, 5, 0]\n"
         "look_at = [0, 0, 0]\nup = [0, 0, -1]\nview_width = 0.02\n[[material]]\nname = \"floor\"\n"
         "color = 0.5\n[[object]]\ntype = \"plane\"\npoint = [0, -1, 0]\nmaterial = \"floor\"\n"
         "[[light]]\ntype = \"sphere\"\nradius = " +
         r + "\nradiance = " + radiance + "\n";
}

TEST(TinySphereLight, IsAPointLightInTheLimitWithoutNaNSamples) {
  for (const auto& [r, radiance] :
       {std::pair{"1e-4", "1e8"}, std::pair{"1e-10", "1e20"}, std::pair{"1e-18", "1e36"}}) {
    const test::Rendered out = test::render_text(tiny_light_scene(r, radiance));
    EXPECT_EQ(out.stats.nan_samples, 0u) << "radius " << r;
    const Color c = out.film->pixel(4, 4);
    EXPECT_NEAR(c.x, 0.5, 0.01) << "radius " << r;
  }
  // Radius 1e-200: no solid angle in double precision, no light, and no NaN either.
  const test::Rendered none = test::render_text(tiny_light_scene("1e-200", "1"));
  EXPECT_EQ(none.stats.nan_samples, 0u);
  EXPECT_EQ(none.film->pixel(4, 4).x, 0);
}

TEST(TinySphereLight, ConeAndPowerHeuristicStayFinite) {
  EXPECT_NEAR(sphere_cone_one_minus_cos(1e-40, 1) / 5e-41, 1, 1e-12);  // (1 - cos rounds to 0)
  EXPECT_NEAR(sphere_cone_one_minus_cos(0.25, 1), 1 - std::sqrt(0.75), 1e-15);
  EXPECT_EQ(sphere_cone_one_minus_cos(1e-320, 1e10), 0);
  EXPECT_EQ(power_heuristic(1e200, 1), 1);
  EXPECT_EQ(power_heuristic(1, 1e200), 0);
  EXPECT_NEAR(power_heuristic(3e200, 1e200), 0.9, 1e-15);
  EXPECT_EQ(power_heuristic(INFINITY, INFINITY), 0.5);
  EXPECT_NEAR(power_heuristic(3, 1), 0.9, 1e-15);  // (the ordinary range, unchanged)
}

TEST(FilmRange, SamplesBeyondSinglePrecisionAreDroppedAndCounted) {
  // Radiance 1e38 x strength 1e10 on every pixel: stored, it would be inf.
  const test::Rendered out = test::render_text(
      "[image]\nwidth = 4\nheight = 4\n[render]\nintegrator = \"path\"\nspp = 2\n"
      "[environment]\ncolor = 1e38\nstrength = 1e10\n");
  EXPECT_EQ(out.stats.nan_samples, 32u);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) EXPECT_TRUE(is_finite(out.film->pixel(x, y))) << x << ", " << y;
}

}  // namespace
}  // namespace anamorph
