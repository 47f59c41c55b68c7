// The solver's derivative of a point's image position with respect to a camera key
// (solve::image_position_derivative: the implicit function theorem with the camera's ray
// differentials, docs/solve.md "How it solves") against the finite differences of the whole inverse
// map (`Camera::project` of the cameras with the key moved), on cameras with coins: a
// perspective camera with a coin over some of the points (fov, look_at, look_from, the coin's
// strength and radius), and a tilted dome with a coin (tilt, fov, strength). Image positions in
// units of the image (u, v in [0, 1]) per unit of the key. And the whole chain rule
// (solve::Goals::derivative) for the kinds whose residuals are functions of several image
// positions or of the rays there (size, straight, magnification) against differences of their
// residuals measured with the whole inverse map.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "params/toml_parse.h"
#include "scene/camera_goals.h"
#include "scene/scene_loader.h"
#include "scene/toml_reader.h"
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

// VirtualCamera::key_derivative (exact: dual numbers through the coins and the rig) against
// central differences (+-h) of the rays of the cameras rebuilt by the scene reader with the key
// moved (the solver's fallback), at image positions on a coin's centre, inside its radius and off
// it. Within 1e-6 per unit of the key (relative where larger than 1).
void expect_ray_derivatives_agree(const std::string& text, const std::string& key,
                                  const CameraKey& ck, double k0) {
  const Scene s0 = at(text, key, k0);
  const double h = 1e-6 * std::max(1.0, std::abs(k0));
  const Scene lo = at(text, key, k0 - h), hi = at(text, key, k0 + h);
  ASSERT_FALSE(coin_sites(*s0.camera).empty()) << key;
  const CoinSite site = coin_sites(*s0.camera)[0];
  double worst = 0;
  for (const Vec2 uv : {site.uv, site.uv + Vec2{0.5, 0.3} * site.radius, Vec2{0.25, 0.7}}) {
    CameraSample cs;
    cs.uv = uv;
    const std::optional<CameraRay> a = lo.camera->generate(cs), b = hi.camera->generate(cs);
    ASSERT_TRUE(a && b) << key;
    Vec3 dorg, ddir;
    ASSERT_TRUE(s0.camera->key_derivative(ck, uv, &dorg, &ddir)) << key;
    const Vec3 fo = (b->org - a->org) / (2 * h), fd = (b->dir - a->dir) / (2 * h);
    const double e = std::max(length(dorg - fo) / std::max(1.0, length(fo)),
                              length(ddir - fd) / std::max(1.0, length(fd)));
    worst = std::max(worst, e);
    EXPECT_LT(e, 1e-6) << key << " at " << k0 << ", uv " << uv.x << "," << uv.y << ": dorg "
                       << dorg.x << "," << dorg.y << "," << dorg.z << " vs " << fo.x << "," << fo.y
                       << "," << fo.z << "; ddir " << ddir.x << "," << ddir.y << "," << ddir.z
                       << " vs " << fd.x << "," << fd.y << "," << fd.z;
  }
  std::printf("%-32s worst %.2g\n", key.c_str(), worst);
}

TEST(SolveJacobian, ExactRayDerivativesAgreeWithDifferencesOfRebuiltCameras) {
  const std::string dir_coin = std::string(kPerspective) + "affects = \"dir\"\nstiffness = 3\n";
  const std::string org_coin = std::string(kPerspective) + "affects = \"org\"\n";
  for (const std::string& text : {std::string(kPerspective), dir_coin, org_coin}) {
    expect_ray_derivatives_agree(text, "camera.coin.0.strength={}", {0, "strength", 0}, 0.3);
    expect_ray_derivatives_agree(text, "camera.coin.0.radius={}", {0, "radius", 0}, 0.15);
    expect_ray_derivatives_agree(text, "camera.coin.0.stiffness={}", {0, "stiffness", 0}, 2);
    expect_ray_derivatives_agree(text, "camera.coin.0.position=[0.6, {}, 0.6]", {0, "position", 1},
                                 0.2);
    expect_ray_derivatives_agree(text, "camera.fov={}", {-1, "fov", 0}, 50);
    expect_ray_derivatives_agree(text, "camera.look_at=[{}, 0, 0]", {-1, "look_at", 0}, 0);
    expect_ray_derivatives_agree(text, "camera.look_from=[0, 1, {}]", {-1, "look_from", 2}, 5);
    expect_ray_derivatives_agree(text, "camera.up=[{}, 1, 0]", {-1, "up", 0}, 0.1);
  }
  // A transform before the rig keeps the rig's derivative (a factor on its right).
  std::string turned = kPerspective;
  turned.replace(turned.find("fov = 50\n"), 9,
                 "fov = 50\ntransform = { rotate = [30, 0, 1, 0] }\n");
  expect_ray_derivatives_agree(turned, "camera.look_at=[0, {}, 0]", {-1, "look_at", 1}, 0);
  for (const auto& [key, ck, k0] : std::vector<std::tuple<std::string, CameraKey, double>>{
           {"camera.tilt={}", {-1, "tilt", 0}, 30},
           {"camera.fov={}", {-1, "fov", 0}, 200},
           {"camera.look_at=[{}, 0, 0]", {-1, "look_at", 0}, 0},
           {"camera.coin.0.strength={}", {0, "strength", 0}, 0.4},
           {"camera.coin.0.position=[{}, -0.4, 1]", {0, "position", 0}, -2}})
    expect_ray_derivatives_agree(kDome, key, ck, k0);
}

const char* kGoals =
    "[[camera.constraint]]\nkind = \"size\"\nfrom = [0.4, 0.1, 0.6]\nto = [0.8, 0.3, 0.5]\n"
    "fraction = 0.1\n[[camera.constraint]]\nkind = \"straight\"\nfrom = [-1.5, 0.6, 0]\n"
    "to = [1.2, 0.1, 0.7]\nsamples = 8\n[[camera.constraint]]\nkind = \"magnification\"\n"
    "point = [0.62, 0.22, 0.6]\nmagnification = 2\n[[camera.free]]\nkey = \"camera.fov\"\n";

// Goals::derivative of each constraint of kGoals against central differences (+-h2) of its
// residuals measured exactly (the whole inverse map).
void expect_chain_rule_agrees(const std::string& key, double k0) {
  const std::string text = std::string(kPerspective) + kGoals;
  const Scene s0 = at(text, key, k0);
  const toml::table root = parse_toml(s0.effective_toml);
  const CameraGoals g =
      read_camera_goals(TableReader(*root.get_as<toml::table>("camera"), "camera"));
  const solve::Goals goals(g, s0, *s0.camera, 320, 240);
  const double h = 1e-6 * std::max(1.0, std::abs(k0)), h2 = 1e-4 * std::max(1.0, std::abs(k0));
  const Scene lo = at(text, key, k0 - h), hi = at(text, key, k0 + h);
  const Scene lo2 = at(text, key, k0 - h2), hi2 = at(text, key, k0 + h2);
  const Scene plain = load_scene_from_string(
      fmt::format("[image]\nwidth = 320\nheight = 240\n[camera]\nlook_from = [0, 1, 5]\n"
                  "look_at = [0, 0, 0]\nfov = 50\n"),
      "plain.toml",
      key.starts_with("camera.coin")
          ? std::vector<std::string>{}
          : std::vector<std::string>{fmt::format(fmt::runtime(key), k0)});
  const auto pair = [&](const Scene& s) {
    return solve::CameraPair{s.camera.get(), plain.camera.get()};
  };
  for (size_t i = 0; i < goals.size(); ++i) {
    const size_t m = size_t(goals.residual_count(i));
    const std::vector<Vec2> uv = goals.positions(i, *s0.camera, true);
    std::vector<double> col(m), rlo(m), rhi(m);
    ASSERT_TRUE(goals.derivative(i, pair(s0), pair(lo), pair(hi), 2 * h, uv,
                                 goals.by_positions(i, pair(s0), uv), col.data()))
        << goals.constraint(i).kind << " " << key;
    goals.residuals(i, pair(lo2), rlo.data(), true);
    goals.residuals(i, pair(hi2), rhi.data(), true);
    for (size_t j = 0; j < m; ++j) {
      const double fd = (rhi[j] - rlo[j]) / (2 * h2);
      // (Residuals in pixels or percent per unit of the key.)
      EXPECT_NEAR(col[j], fd, 1e-4 * std::max(1.0, std::abs(fd)))
          << goals.constraint(i).kind << " residual " << j << ", " << key << " at " << k0
          << ": chain rule " << col[j] << " vs differences " << fd;
    }
  }
}

// (The camera without coins, for magnification, is held at k0 on both sides.)
TEST(SolveJacobian, ChainRuleAgreesWithDifferencesForSizeStraightAndMagnification) {
  for (const auto& [key, k0] :
       std::vector<std::pair<std::string, double>>{{"camera.fov={}", 50},
                                                   {"camera.look_at=[{}, 0, 0]", 0},
                                                   {"camera.coin.0.strength={}", 0.3},
                                                   {"camera.coin.0.radius={}", 0.15}})
    expect_chain_rule_agrees(key, k0);
}

}  // namespace
}  // namespace anamorph
