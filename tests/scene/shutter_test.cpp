// Camera motion blur and rolling shutter: a ray's time picks the rig between shutter open and
// close.
#include <gtest/gtest.h>

#include "scene/scene_loader.h"
#include "scene/toml_reader.h"

namespace anamorph {

namespace {
const std::string kMoving =
    "[image]\nwidth = 10\nheight = 10\n"
    "[camera]\nlook_from = [0, 0, 5]\nlook_at = [0, 0, 0]\nfov = 40\nshutter = [0, 1]\n"
    "[[animate]]\nkey = \"camera.look_from\"\nkeys = [[0, [0, 0, 5]], [1, [2, 0, 5]]]\n"
    "[[animate]]\nkey = \"camera.look_at\"\nkeys = [[0, [0, 0, 0]], [1, [2, 0, 0]]]\n";

Vec3 origin(const Scene& s, Vec2 uv, double time) {
  CameraSample cs;
  cs.uv = uv;
  cs.time = time;
  return s.camera->generate(cs)->org;
}
}  // namespace

TEST(Shutter, MotionBlurInterpolatesTheRig) {
  const Scene s = load_scene_from_string(kMoving, "t.toml");
  EXPECT_NEAR(length(origin(s, {0.5, 0.5}, 0) - Vec3{0, 0, 5}), 0, 1e-12);
  EXPECT_NEAR(length(origin(s, {0.5, 0.5}, 1) - Vec3{2, 0, 5}), 0, 1e-12);
  EXPECT_NEAR(length(origin(s, {0.5, 0.5}, 0.25) - Vec3{0.5, 0, 5}), 0, 1e-12);
  // Without a shutter interval the camera is the frame's, whatever the sample time.
  const Scene still = load_scene_from_string(kMoving, "t.toml", {"camera.shutter=[0, 0]"});
  EXPECT_NEAR(length(origin(still, {0.5, 0.5}, 0.9) - Vec3{0, 0, 5}), 0, 1e-12);
}

TEST(Shutter, RotationIsSlerpedNotStretched) {
  const Scene s = load_scene_from_string(
      "[camera]\nlook_from = [0, 0, 0]\nlook_at = [0, 0, -1]\nshutter = [0, 1]\n"
      "[[animate]]\nkey = \"camera.look_at\"\nkeys = [[0, [0, 0, -1]], [1, [1, 0, 0]]]\n",
      "t.toml");
  CameraSample cs;
  cs.uv = {0.5, 0.5};
  cs.time = 0.5;
  const Vec3 d = s.camera->generate(cs)->dir;
  EXPECT_NEAR(length(d - normalize(Vec3{1, 0, -1})), 0, 1e-9) << d.x << " " << d.y << " " << d.z;
}

TEST(Shutter, RollingShutterTimeFollowsTheImageRows) {
  const Scene s =
      load_scene_from_string(kMoving, "t.toml", {"camera.rolling_shutter=top_to_bottom"});
  // Top row: shutter open; bottom row: shutter close; the sample's own time is ignored.
  const Vec3 top = origin(s, {0.5, 0.0}, 0.7), bottom = origin(s, {0.5, 1.0}, 0.7),
             mid = origin(s, {0.5, 0.5}, 0.1);
  EXPECT_NEAR(top.x, 0, 1e-12);
  EXPECT_NEAR(bottom.x, 2, 1e-12);
  EXPECT_NEAR(mid.x, 1, 1e-12);
  const Scene lr =
      load_scene_from_string(kMoving, "t.toml", {"camera.rolling_shutter=right_to_left"});
  EXPECT_NEAR(origin(lr, {1.0, 0.3}, 0.5).x, 0, 1e-12);
  EXPECT_NEAR(origin(lr, {0.0, 0.3}, 0.5).x, 2, 1e-12);
}

TEST(Shutter, BadShutterIsAnError) {
  EXPECT_THROW(load_scene_from_string("[camera]\nshutter = [1, 0]\n", "t.toml"), SceneError);
  EXPECT_THROW(load_scene_from_string("[camera]\nrolling_shutter = \"sideways\"\n", "t.toml"),
               SceneError);
}

}  // namespace anamorph
