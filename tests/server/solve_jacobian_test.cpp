// The solver's derivative of a point's image position with respect to a camera key
// (solve::image_position_derivative: the implicit function theorem with the camera's ray
// differentials, docs/solve.md "How it solves") against the finite differences of the whole inverse
// map (`Camera::project` of the cameras with the key moved), on cameras with coins: a
// perspective camera with a coin over some of the points (fov, look_at, look_from, the coin's
// strength and radius), and a tilted dome with a coin (tilt, fov, strength). Image positions in
// units of the image (u, v in [0, 1]) per unit of the key.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "scene/scene_loader.h"
#include "solve/goals.h"

namespace anamorph {
namespace {

const char* kPerspective =
    "[image]\nwidth = 320\nheight = 240\n[camera]\nlook_from = [0, 1, 5]\nlook_at = [0, 0, 0]\n"
    "fov = 50\n[[camera.coin]]\nposition = [0.6, 0.2, 0.6]\nstrength = 0.3\nradius = 0.15\n";
const char* kDome =
    "[image]\nwidth = 320\nheight = 320\n[camera]\npreset = \"dome\"\nlook_from = [0, 0, 4]\n"
    "look_at = [0, 0, 0]\nfov = 200\ntilt = 30\n[[camera.coin]]\nposition = [-2, -0.4, 1]\n"
    "affects = \"dir\"\nstrength = 0.4\nradius = 0.2\nstiffness = 3\n";

// The scene with the override `set` ("camera.fov={}") given `value`.
Scene at(const std::string& text, const std::string& set, double value) {
  return load_scene_from_string(text, "jacobian.toml",
                                {fmt::format(fmt::runtime(set), fmt::format("{:.17g}", value))});
}

// The image position of p nearest to `near` (the whole inverse map).
Vec2 nearest(const Camera& cam, const Vec3& p, Vec2 near) {
  const std::vector<Vec2> all = cam.project(p);
  EXPECT_FALSE(all.empty());
  Vec2 best{NAN, NAN};
  for (const Vec2& q : all)
    if (!(length(best - near) <= length(q - near))) best = q;
  return best;
}

void expect_derivatives_agree(const std::string& text, const std::string& key, double k0,
                              const std::vector<Vec3>& points) {
  const Scene s0 = at(text, key, k0);
  const double h = 1e-6 * std::max(1.0, std::abs(k0)), h2 = 1e-4 * std::max(1.0, std::abs(k0));
  const Scene lo = at(text, key, k0 - h), hi = at(text, key, k0 + h);
  const Scene lo2 = at(text, key, k0 - h2), hi2 = at(text, key, k0 + h2);
  for (const Vec3& p : points) {
    const std::vector<Vec2> seen = s0.camera->project(p);
    ASSERT_FALSE(seen.empty()) << key << " " << p.x << "," << p.y << "," << p.z;
    const Vec2 uv = seen[0];
    Vec2 d;
    ASSERT_TRUE(
        solve::image_position_derivative(*s0.camera, *lo.camera, *hi.camera, 2 * h, p, uv, &d));
    const Vec2 fd = (nearest(*hi2.camera, p, uv) - nearest(*lo2.camera, p, uv)) * (0.5 / h2);
    const double scale = std::max(1.0, length(fd));
    // (Measured: at most 1.6e-8, the radius's at the coin's rim; the differences of the inverse
    // map carry its 1e-12 convergence over 2e-4 of the key.)
    EXPECT_LT(length(d - fd), 1e-7 * scale)
        << key << " at " << k0 << ", point " << p.x << "," << p.y << "," << p.z << ": analytic "
        << d.x << "," << d.y << " vs differences " << fd.x << "," << fd.y;
  }
}

TEST(SolveJacobian, ImagePositionDerivativesAgreeWithDifferencesOfTheInverseMap) {
  // Points off the coin, on its rim and at its centre.
  const std::vector<Vec3> persp = {{1, 0, 0}, {-1, 0.5, 0}, {0.6, 0.2, 0.6}, {0.7, 0.25, 0.6}};
  for (const auto& [key, k0] :
       std::vector<std::pair<std::string, double>>{{"camera.fov={}", 50},
                                                   {"camera.look_at=[{}, 0, 0]", 0},
                                                   {"camera.look_from=[0, {}, 5]", 1},
                                                   {"camera.coin.0.strength={}", 0.3},
                                                   {"camera.coin.0.radius={}", 0.15}})
    expect_derivatives_agree(kPerspective, key, k0, persp);
  const std::vector<Vec3> dome = {{-2, -0.4, 1}, {-1.8, -0.3, 1}, {1.5, -0.3, -1.7}};
  for (const auto& [key, k0] : std::vector<std::pair<std::string, double>>{
           {"camera.tilt={}", 30}, {"camera.fov={}", 200}, {"camera.coin.0.strength={}", 0.4}})
    expect_derivatives_agree(kDome, key, k0, dome);
}

}  // namespace
}  // namespace anamorph
