// Keyframed scene keys.
#include <gtest/gtest.h>

#include <cmath>

#include "scene/animation.h"
#include "scene/scene_loader.h"

namespace anamorph {

namespace {
const std::string kScene =
    "[image]\nwidth = 8\nheight = 6\n"
    "[camera]\nlook_from = [0, 1, 5]\nlook_at = [0, 0, 0]\nfov = 50\n"
    "[[object]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\n"
    "[[animate]]\nkey = \"camera.fov\"\nkeys = [[0, 50], [10, 30], [20, 60]]\ninterpolation = "
    "\"smooth\"\n"
    "[[animate]]\nkey = \"object.0.center\"\nkeys = [[0, [0, 0, 0]], [10, [2, 4, -6]]]\n";

double fov_of(const Scene& s) {
  const auto a = s.camera->generate({{0.0, 0.5}}), b = s.camera->generate({{1.0, 0.5}});
  return degrees(std::acos(dot(a->dir, b->dir)));
}
}  // namespace

TEST(Animation, ExactAtKeysAndClampedOutside) {
  for (auto [frame, want] :
       {std::pair{0.0, 50.0}, {10.0, 30.0}, {20.0, 60.0}, {-5.0, 50.0}, {99.0, 60.0}})
    EXPECT_NEAR(fov_of(load_scene_from_string(kScene, "t.toml", {}, frame)), want, 1e-9)
        << "frame " << frame;
}

TEST(Animation, LinearVectorsInterpolateComponentwise) {
  const Scene s = load_scene_from_string(kScene, "t.toml", {}, 2.5);
  const Vec3 c = s.shapes[0].world_from_object.point({0, 0, 0});
  EXPECT_NEAR(length(c - Vec3{0.5, 1, -1.5}), 0, 1e-12);
}

TEST(Animation, SmoothIsC1AndPassesThroughKeys) {
  toml::table t = toml::parse(kScene);
  const auto anim = take_animation(t);
  ASSERT_EQ(anim.size(), 2u);
  const AnimatedKey& a = anim[0];
  // The slope is continuous across the middle key.
  const double h = 1e-6;
  const double left = (evaluate(a, 10)[0] - evaluate(a, 10 - h)[0]) / h;
  const double right = (evaluate(a, 10 + h)[0] - evaluate(a, 10)[0]) / h;
  EXPECT_NEAR(left, right, 1e-4);
  EXPECT_DOUBLE_EQ(evaluate(a, 10)[0], 30);
}

TEST(Animation, AFrameEqualsAStillWithTheValuesSet) {
  const double f = 7.25;
  const Scene animated = load_scene_from_string(kScene, "t.toml", {}, f);
  toml::table t = toml::parse(kScene);
  const auto anim = take_animation(t);
  const double fov = evaluate(anim[0], f)[0];
  const auto c = evaluate(anim[1], f);
  const Scene still =
      load_scene_from_string(kScene, "t.toml",
                             {"camera.fov=" + std::to_string(fov),
                              "object.0.center=[" + std::to_string(c[0]) + "," +
                                  std::to_string(c[1]) + "," + std::to_string(c[2]) + "]"},
                             0);
  EXPECT_NEAR(fov_of(animated), fov_of(still), 1e-5);
  EXPECT_NEAR(length(animated.shapes[0].world_from_object.point({}) -
                     still.shapes[0].world_from_object.point({})),
              0, 1e-5);
}

TEST(Animation, BadDefinitionsAreLocatedErrors) {
  auto err = [](const std::string& a) {
    try {
      load_scene_from_string("[camera]\nfov = 50\n" + a, "t.toml");
    } catch (const SceneError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(err("[[animate]]\nkey = \"camera.fov\"\nkeys = [[5, 1], [2, 3]]\n").find("increase"),
            std::string::npos);
  EXPECT_NE(err("[[animate]]\nkey = \"camera.fov\"\nkeys = [[0, \"a\"]]\n").find("finite numbers"),
            std::string::npos);
  EXPECT_NE(err("[[animate]]\nkey = \"camera.fov\"\nkeys = [[0, 1]]\ninterpolation = \"cubic\"\n")
                .find("smooth"),
            std::string::npos);
  EXPECT_NE(err("[[animate]]\nkey = \"camera.fvo\"\nkeys = [[0, 40]]\n").find("did you mean 'fov'"),
            std::string::npos);
}

}  // namespace anamorph
