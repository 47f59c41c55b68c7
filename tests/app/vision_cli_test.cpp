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
std::string turning_scene(bool moving, bool coin = false) {
  std::string s =
      "[image]\nwidth = 40\nheight = 32\n[render]\nintegrator = \"albedo\"\n"
      "sampler = \"center\"\n[camera]\npreset = \"fisheye\"\nfov = 160\n"
      "look_from = [0, 0, 0]\nlook_at = [0, 0, -1]\n"
      "[[object]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 20\n"
      "[[object]]\ntype = \"sphere\"\ncenter = [0, 0, -3]\nradius = 1\n"
      "[[animate]]\nkey = \"camera.look_at\"\nkeys = [[0, [0, 0, -1]], [2, [0.1, 0.04, -1]]]\n";
  if (moving)
    s += "[[animate]]\nkey = \"object.1.center\"\nkeys = [[0, [0, 0, -3]], [2, [0.6, 0, -3]]]\n";
  if (coin)  // a coin on the small sphere, growing: the flow goes through the coin's inverse map
    s += "[[camera.coin]]\nposition = [0, 0, -3]\nstrength = 0.2\nradius = 0.3\n"
         "[[animate]]\nkey = \"camera.coin.0.strength\"\nkeys = [[0, 0.2], [2, 0.6]]\n";
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
  for (const int variant : {0, 1, 2}) {  // the sphere moving; the camera only; with a coin
    const bool moving = variant == 0;
    test::ScratchDir dir{"flow"};
    const std::string file = dir.write("s.toml", turning_scene(moving, variant == 2));
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
        const std::string what = fmt::format(
            "{}, frame {} to {}",
            moving ? "moving" : (variant == 2 ? "growing coin" : "camera only"), frame, other);
        check_flow(ch, W, H, step > 0 ? "flow_forward" : "flow_backward",
                   load_scene(file, {}, other), {moved, 0, 0}, what);
      }
      const auto meta = read_metadata(exr);
      EXPECT_TRUE(meta.count("anamorph.layer.flow_forward")) << "the layer's definition";
    }
  }
}

// `render --aov ray_origin,ray_direction` holds, at every pixel, the ray `anamorph rays` writes
// for it (the same floats), misses included, NaN where `rays` says there is none (valid 0), and
// states the layers' definitions in the header.
TEST(VisionCli, RayLayersAreWhatRaysWrites) {
  for (const std::string preset : {"perspective", "fisheye"}) {
    test::ScratchDir dir{"rays"};
    const std::string file =
        dir.write("s.toml",
                  "[image]\nwidth = 10\nheight = 8\n[render]\nintegrator = \"albedo\"\n"
                  "spp = 2\n[camera]\npreset = \"" +
                      preset +
                      "\"\nfov = 120\nlook_from = [1, 2, 3]\nlook_at = [0, 0, 0]\n"
                      "[[object]]\ntype = \"sphere\"\nradius = 1\n");
    const fs::path exr = dir.dir / "a.exr", rays = dir.dir / "r.exr";
    const test::CliResult r = test::run_cli("render " + file + " -o " + exr.string() +
                                            " --aov ray_origin,ray_direction,id -q");
    ASSERT_EQ(r.code, 0) << r.out;
    ASSERT_EQ(test::run_cli("rays " + file + " -o " + rays.string()).code, 0);
    int W = 0, H = 0, rw = 0, rh = 0;
    const auto a = read_exr_channels(exr, &W, &H), t = read_exr_channels(rays, &rw, &rh);
    ASSERT_EQ(W, rw);
    int no_ray = 0, misses = 0;
    for (size_t i = 0; i < size_t(W) * size_t(H); ++i) {
      no_ray += t.at("valid.V")[i] == 0;
      misses += a.at("id.id")[i] < 0;
      for (const char* c : {"X", "Y", "Z"}) {
        const float o = a.at(std::string("ray_origin.") + c)[i],
                    d = a.at(std::string("ray_direction.") + c)[i];
        if (t.at("valid.V")[i] == 0) {
          EXPECT_TRUE(std::isnan(o) && std::isnan(d)) << preset << " pixel " << i << ": " << o;
        } else {
          EXPECT_EQ(o, t.at(std::string("org.") + c)[i]) << preset << " pixel " << i << " " << c;
          EXPECT_EQ(d, t.at(std::string("dir.") + c)[i]) << preset << " pixel " << i << " " << c;
        }
      }
    }
    EXPECT_EQ(no_ray > 0, preset == "fisheye") << no_ray;
    EXPECT_GT(misses, 10) << preset;
    const auto meta = read_metadata(exr);
    EXPECT_TRUE(meta.count("anamorph.layer.ray_origin") &&
                meta.count("anamorph.layer.ray_direction"));
    std::printf("%s: %d misses, %d pixels without a ray\n", preset.c_str(), misses, no_ray);
  }
}

// A .flo file's (u, v) floats (Middlebury: the tag 202021.25, width, height, then u, v row by
// row); empty when its header is not that.
std::vector<float> read_flo(const fs::path& file, int W, int H) {
  std::FILE* f = std::fopen(file.c_str(), "rb");
  if (!f) return {};
  float tag = 0;
  int32_t size[2] = {0, 0};
  std::vector<float> uv(size_t(W) * size_t(H) * 2);
  const bool ok = std::fread(&tag, 4, 1, f) == 1 && std::fread(size, 4, 2, f) == 2 &&
                  tag == 202021.25f && size[0] == W && size[1] == H &&
                  std::fread(uv.data(), 4, uv.size(), f) == uv.size() && std::fgetc(f) == EOF;
  std::fclose(f);
  return ok ? uv : std::vector<float>{};
}

// `-o f.flo --aov flow_forward` writes the .flo and, beside it, the EXR with the beauty and the
// flow: the .flo's u, v are the EXR's flow_forward.X, .Y bit for bit, 1e10 (the format's unknown
// flow) where the EXR has NaN; OpenCV's reader (cv2.readOpticalFlow) reads the same numbers.
// With only flow_backward, that is the .flo's.
TEST(VisionCli, FloFilesHoldTheFlowLayer) {
  test::ScratchDir dir{"flo"};
  const std::string file = dir.write("s.toml", turning_scene(true));
  for (const std::string layer : {"flow_forward", "flow_backward"}) {
    const std::string aovs = layer == "flow_forward" ? "flow_forward,flow_backward" : layer;
    const test::CliResult r = test::run_cli("render " + file + " --frames 1:1 -o " +
                                            (dir.dir / "f_%04d.flo").string() + " --aov " + aovs);
    ASSERT_EQ(r.code, 0) << r.out;
    int W = 0, H = 0;
    const auto ch = read_exr_channels(dir.dir / "f_0001.exr", &W, &H);
    const std::vector<float> uv = read_flo(dir.dir / "f_0001.flo", W, H);
    ASSERT_FALSE(uv.empty()) << "not a " << W << " x " << H << " .flo file";
    int unknown = 0;
    for (size_t i = 0; i < size_t(W) * size_t(H); ++i)
      for (const int c : {0, 1}) {
        const float e = ch.at(layer + (c ? ".Y" : ".X"))[i];
        unknown += std::isnan(e) && c == 0;
        EXPECT_EQ(uv[2 * i + size_t(c)], std::isnan(e) ? 1e10f : e) << layer << " value " << i;
      }
    EXPECT_GT(unknown, 0) << "pixels outside the fisheye's circle have no flow";
    std::printf("%s: %d x %d .flo equal to the EXR, %d pixels unknown\n", layer.c_str(), W, H,
                unknown);
    if (layer != "flow_forward") continue;  // (OpenCV's reader once)
    if (test::run_shell("/usr/bin/python3 -c 'import cv2, numpy'").code != 0) {
      std::printf("/usr/bin/python3 without cv2: the OpenCV cross-check is skipped\n");
      continue;
    }
    const fs::path raw = dir.dir / "cv2.raw";
    const test::CliResult py = test::run_shell(
        "/usr/bin/python3 -c 'import cv2, sys; "
        "cv2.readOpticalFlow(sys.argv[1]).tofile(sys.argv[2])' " +
        (dir.dir / "f_0001.flo").string() + " " + raw.string());
    ASSERT_EQ(py.code, 0) << py.out;
    std::FILE* f = std::fopen(raw.c_str(), "rb");
    ASSERT_NE(f, nullptr);
    std::vector<float> cv(uv.size() + 1);
    const size_t n = std::fread(cv.data(), 4, cv.size(), f);
    std::fclose(f);
    ASSERT_EQ(n, uv.size()) << "cv2's array is not H x W x 2";
    cv.pop_back();
    EXPECT_EQ(cv, uv) << "cv2.readOpticalFlow reads other numbers";
  }
  const test::CliResult bad =
      test::run_cli("render " + file + " -o " + (dir.dir / "g.flo").string() + " --aov distance");
  EXPECT_EQ(bad.code, 2) << bad.out;
  EXPECT_NE(bad.out.find("g.flo"), std::string::npos) << bad.out;
  EXPECT_FALSE(fs::exists(dir.dir / "g.flo"));
}

// The same scene for Blender (a script building it: camera and a unit cube keyed at frames 0, 1,
// 2, a 40 x 40 plane behind) and for anamorph; Blender's world is z up, as the TOML says with
// `up`. Camera 50 degrees wide, looking along +y.
const char* kCyclesScript = R"(import bpy, sys, math
out = sys.argv[sys.argv.index("--") + 1]
sc = bpy.context.scene
for o in list(bpy.data.objects):
    bpy.data.objects.remove(o)
sc.render.engine = "CYCLES"
sc.cycles.device = "CPU"
sc.cycles.samples = 1
sc.cycles.use_denoising = False
sc.cycles.filter_width = 0.01  # (samples at the pixel centre)
sc.render.use_motion_blur = False  # (the Vector pass needs it off)
sc.render.resolution_x, sc.render.resolution_y, sc.render.resolution_percentage = 48, 36, 100
sc.view_layers[0].use_pass_vector = True
cd = bpy.data.cameras.new("cam")
cd.sensor_fit = "HORIZONTAL"
cd.angle = math.radians(50)
cam = bpy.data.objects.new("cam", cd)
sc.collection.objects.link(cam)
sc.camera = cam
cam.rotation_euler = (math.pi / 2, 0, 0)
def keys(obj, pts):
    for f, p in enumerate(pts):
        obj.location = p
        obj.keyframe_insert("location", frame=f)
keys(cam, [(-0.2, -6, 0.5), (0, -6, 0.5), (0.3, -6.2, 0.6)])
bpy.ops.mesh.primitive_cube_add(size=1)
keys(bpy.context.active_object, [(-0.4, -0.5, 0.2), (0, 0, 0.5), (0.5, 0.6, 0.9)])
bpy.ops.mesh.primitive_plane_add(size=40, location=(0, 3, 0), rotation=(math.pi / 2, 0, 0))
sc.frame_set(1)
sc.render.image_settings.file_format = "OPEN_EXR_MULTILAYER"
sc.render.image_settings.color_depth = "32"
sc.render.filepath = out
bpy.ops.render.render(write_still=True)
)";

const char* kCyclesScene = R"([image]
width = 48
height = 36
[render]
integrator = "albedo"
sampler = "center"
[camera]
preset = "perspective"
fov = 50
look_from = [-0.2, -6, 0.5]
look_at = [-0.2, -5, 0.5]
up = [0, 0, 1]
[[object]]
type = "box"
[[object]]
type = "rectangle"
center = [0, 3, 0]
edge_u = [40, 0, 0]
edge_v = [0, 0, 40]
[[animate]]
key = "camera.look_from"
keys = [[0, [-0.2, -6, 0.5]], [1, [0, -6, 0.5]], [2, [0.3, -6.2, 0.6]]]
[[animate]]
key = "camera.look_at"
keys = [[0, [-0.2, -5, 0.5]], [1, [0, -5, 0.5]], [2, [0.3, -5.2, 0.6]]]
[[animate]]
key = "object.0.center"
keys = [[0, [-0.4, -0.5, 0.2]], [1, [0, 0, 0.5]], [2, [0.5, 0.6, 0.9]]]
)";

// An independent tool: anamorph's `motion` layer against Blender Cycles' Vector pass of the same
// scene at frame 1 (a moving camera, a moving cube, a still plane), away from silhouettes.
TEST(VisionCli, MotionLayerMatchesCyclesVectorPass) {
  if (test::run_shell("command -v blender").code != 0)
    GTEST_SKIP() << "blender not installed (Debian's blender): the Cycles comparison is skipped";
  test::ScratchDir dir{"cycles"};
  const std::string script = dir.write("cycles.py", kCyclesScript);
  const fs::path cycles_exr = dir.dir / "cycles.exr";
  const test::CliResult b = test::run_shell("blender -b --factory-startup --python " + script +
                                            " -- " + cycles_exr.string());
  ASSERT_EQ(b.code, 0) << b.out;
  ASSERT_TRUE(fs::exists(cycles_exr)) << b.out;
  const std::string scene = dir.write("s.toml", kCyclesScene);
  const test::CliResult r =
      test::run_cli("render " + scene + " --frames 1:1 -o " + (dir.dir / "a_%04d.exr").string() +
                    " --aov motion,id -q");
  ASSERT_EQ(r.code, 0) << r.out;
  int W = 0, H = 0, cw = 0, chh = 0;
  const auto a = read_exr_channels(dir.dir / "a_0001.exr", &W, &H);
  const auto c = read_exr_channels(cycles_exr, &cw, &chh);
  ASSERT_EQ(W, cw);
  ASSERT_EQ(H, chh);
  const char* xyzw = "XYZW";
  int compared = 0, cube = 0;
  double worst = 0, largest = 0;
  for (int y = 1; y + 1 < H; ++y)
    for (int x = 1; x + 1 < W; ++x) {
      const auto id = [&](int dx, int dy) {
        return a.at("id.id")[size_t(y + dy) * size_t(W) + size_t(x + dx)];
      };
      bool inside = true;  // the 3 x 3 pixels see the same object
      for (int k = 0; k < 9; ++k) inside = inside && id(k % 3 - 1, k / 3 - 1) == id(0, 0);
      if (!inside || id(0, 0) < 0) continue;
      ++compared;
      cube += id(0, 0) == 0;
      const size_t i = size_t(y) * size_t(W) + size_t(x);
      for (int k = 0; k < 4; ++k) {
        const double mine = a.at(std::string("motion.") + xyzw[k])[i];
        const double theirs = c.at(std::string("ViewLayer.Vector.") + xyzw[k])[i];
        EXPECT_NEAR(mine, theirs, 1e-4) << "pixel " << x << "," << y << " channel " << xyzw[k];
        worst = std::max(worst, std::abs(mine - theirs));
        largest = std::max(largest, std::abs(theirs));
      }
    }
  EXPECT_GT(cube, 20);
  EXPECT_GT(compared, W * H / 2);
  EXPECT_GT(largest, 1) << "the scene moves by pixels";
  std::printf("motion vs Cycles' Vector: %d pixels (%d of the cube), worst %.3g px of up to %.3g\n",
              compared, cube, worst, largest);
}

}  // namespace
}  // namespace anamorph
