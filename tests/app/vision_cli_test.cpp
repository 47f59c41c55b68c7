// `render --aov flow_forward,flow_backward`: the command loads frames + 1 and - 1 beside each frame
// (the whole scene when objects move, only the view when the camera alone does), and each pixel's
// flow is where that frame's camera (Camera::project, what `anamorph project` prints) sees the
// pixel's point, moved with its object, minus the pixel.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "cli_util.h"
#include "io/image_io.h"
#include "run_fixture.h"
#include "scene/scene_loader.h"

namespace anamorph {
namespace {

namespace fs = std::filesystem;

// A 160-degree fisheye at the origin turning between frames 0 and 2, inside a still sphere of
// radius 20, before a sphere of radius 1 that moves by (0.6, 0, 0) over the two frames when
// `moving`.
std::string turning_scene(bool moving) {
  std::string s =
      "[image]\nwidth = 40\nheight = 32\n[render]\nintegrator = \"albedo\"\n"
      "sampler = \"center\"\n[camera]\npreset = \"fisheye\"\nfov = 160\n"
      "look_from = [0, 0, 0]\nlook_at = [0, 0, -1]\n"
      "[[object]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 20\n"
      "[[object]]\ntype = \"sphere\"\ncenter = [0, 0, -3]\nradius = 1\n"
      "[[animate]]\nkey = \"camera.look_at\"\nkeys = [[0, [0, 0, -1]], [2, [0.1, 0.04, -1]]]\n";
  if (moving)
    s += "[[animate]]\nkey = \"object.1.center\"\nkeys = [[0, [0, 0, -3]], [2, [0.6, 0, -3]]]\n";
  return s;
}

// Checks the flow layer `layer` of one frame's channels `ch` against `other`'s camera, the moving
// sphere (id 1) displaced by `move` there.
void check_flow(const std::map<std::string, std::vector<float>>& ch, int W, int H,
                const std::string& layer, const Scene& other, const Vec3& move,
                const std::string& what) {
  int valid = 0;
  double worst = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const size_t i = size_t(y) * size_t(W) + size_t(x);
      if (ch.at(layer + ".valid")[i] != 1) continue;
      ++valid;
      Vec3 p{ch.at("position.X")[i], ch.at("position.Y")[i], ch.at("position.Z")[i]};
      if (ch.at("id.id")[i] == 1) p = p + move;
      const Vec2 uv{(x + 0.5) / W, (y + 0.5) / H};
      double best = 1e300;
      Vec2 flow;
      for (const Vec2& at : other.camera->project(p)) {
        const Vec2 d{(at.x - uv.x) * W, (at.y - uv.y) * H};
        if (d.x * d.x + d.y * d.y < best) best = d.x * d.x + d.y * d.y, flow = d;
      }
      ASSERT_LT(best, 1e300) << what << " pixel " << x << "," << y << " has flow, no projection";
      const double fx = ch.at(layer + ".X")[i], fy = ch.at(layer + ".Y")[i];
      EXPECT_NEAR(fx, flow.x, 1e-3) << what << " pixel " << x << "," << y;
      EXPECT_NEAR(fy, flow.y, 1e-3) << what << " pixel " << x << "," << y;
      worst = std::max({worst, std::abs(fx - flow.x), std::abs(fy - flow.y)});
    }
  EXPECT_GT(valid, W * H / 2) << what;
  std::printf("%s: %d pixels with flow, worst difference %.3g px\n", what.c_str(), valid, worst);
}

TEST(VisionCli, FlowOfASequenceIsTheOtherFramesProjection) {
  for (const bool moving : {true, false}) {
    test::ScratchDir dir{"flow"};
    const std::string file = dir.write("s.toml", turning_scene(moving));
    const std::string out = (dir.dir / "f_%04d.exr").string();
    const test::CliResult r =
        test::run_cli("render " + file + " -o " + out +
                      " --frames 0:1 --aov flow_forward,flow_backward,position,id -q");
    ASSERT_EQ(r.code, 0) << r.out;
    for (int frame = 0; frame <= 1; ++frame) {
      int W = 0, H = 0;
      const fs::path exr = dir.dir / fmt::format("f_{:04d}.exr", frame);
      const auto ch = read_exr_channels(exr, &W, &H);
      for (const int step : {1, -1}) {
        const int other = frame + step;  // the keys hold their values before frame 0
        const double moved = moving ? 0.3 * (std::max(other, 0) - frame) : 0;
        const std::string what =
            fmt::format("{}, frame {} to {}", moving ? "moving" : "camera only", frame, other);
        check_flow(ch, W, H, step > 0 ? "flow_forward" : "flow_backward",
                   load_scene(file, {}, other), {moved, 0, 0}, what);
      }
      const auto meta = read_metadata(exr);
      EXPECT_TRUE(meta.count("anamorph.layer.flow_forward")) << "the layer's definition";
    }
  }
}

}  // namespace
}  // namespace anamorph
