// The vision layers (docs/vision.md): the depth conventions against a plane at a known distance,
// and forward flow against closed-form projections of a panning camera and a moving sphere.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "render/renderer.h"
#include "scene/scene_loader.h"

namespace anamorph {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A frame rendered with `aovs` (its next frame attached, as `render` does for flow), and its layers
// by name.
struct VisionFrame {
  Scene scene;
  OutputImage out;
  const ImageLayer& layer(const std::string& name) const {
    for (const ImageLayer& l : out.layers)
      if (l.name == name) return l;
    throw std::logic_error("no layer " + name);
  }
  // Channel c of layer `name` at pixel (x, y).
  double at(const std::string& name, int x, int y, int c = 0) const {
    const ImageLayer& l = layer(name);
    const size_t nc = l.channels.size();
    return l.data[(size_t(y) * size_t(out.width) + size_t(x)) * nc + size_t(c)];
  }
};

VisionFrame render_frame(const std::string& toml, const std::vector<Aov>& aovs, double frame = 0) {
  VisionFrame f{load_scene_from_string(toml, "vision.toml", {}, frame), {}};
  f.scene.next = frame_motion(load_scene_from_string(toml, "vision.toml", {}, frame + 1));
  f.scene.previous = frame_motion(load_scene_from_string(toml, "vision.toml", {}, frame - 1));
  const Renderer renderer(f.scene);
  Film film(f.scene.render.width, f.scene.render.height, aovs);
  RenderOptions opt;
  opt.aovs = aovs;
  renderer.render(film, opt);
  f.out = film.output();
  return f;
}

std::string image(int w, int h) {
  return "[image]\nwidth = " + std::to_string(w) + "\nheight = " + std::to_string(h) +
         "\n[render]\nintegrator = \"albedo\"\nsampler = \"center\"\n";
}

// The plane z = 0 seen from (0, 0, 5) along -z: every pixel's point is 5 in front of the camera.
void check_plane_depths(const std::string& camera) {
  const int W = 9, H = 9;
  const VisionFrame f = render_frame(image(W, H) + camera +
                                         "look_from = [0, 0, 5]\nlook_at = [0, 0, 0]\n"
                                         "[[object]]\ntype = \"plane\"\nnormal = [0, 0, 1]\n",
                                     {Aov::Depth, Aov::Distance, Aov::DepthZ, Aov::CameraPosition});
  int hits = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const auto ray = f.scene.camera->generate({{(x + 0.5) / W, (y + 0.5) / H}});
      if (!ray || ray->dir.z > -1e-3) continue;
      ++hits;
      const double d = 5 / -ray->dir.z;  // ray distance to the plane
      SCOPED_TRACE(camera + " pixel " + std::to_string(x) + "," + std::to_string(y));
      EXPECT_NEAR(f.at("distance", x, y), d, 1e-5 * d);
      EXPECT_EQ(f.at("depth", x, y), f.at("distance", x, y)) << "depth is the ray distance";
      EXPECT_NEAR(f.at("depth_z", x, y), 5, 1e-5 * d);
      EXPECT_NEAR(f.at("position_camera", x, y, 0), ray->dir.x * d, 1e-5 * d);
      EXPECT_NEAR(f.at("position_camera", x, y, 1), ray->dir.y * d, 1e-5 * d);
      EXPECT_NEAR(f.at("position_camera", x, y, 2), -5, 1e-5 * d);
    }
  EXPECT_GT(hits, 20);
}

TEST(VisionAov, DepthConventionsOnAPlaneAtKnownDistance) {
  check_plane_depths("[camera]\npreset = \"perspective\"\nfov = 90\n");
  check_plane_depths("[camera]\npreset = \"fisheye\"\nfov = 170\n");
}

TEST(VisionAov, MissesHaveInfiniteDepthAndNoFlow) {
  const VisionFrame f =
      render_frame(image(4, 4) + "[camera]\nlook_from = [0, 0, 5]\nlook_at = [0, 0, 0]\n",
                   {Aov::Distance, Aov::DepthZ, Aov::FlowForward});
  EXPECT_TRUE(std::isinf(f.at("distance", 1, 1)));
  EXPECT_TRUE(std::isinf(f.at("depth_z", 1, 1)));
  EXPECT_TRUE(std::isnan(f.at("flow_forward", 1, 1, 0)));
  EXPECT_EQ(f.at("flow_forward", 1, 1, 2), 0) << "valid fraction";
}

// Camera space (x right, y up, looking along -z) of a camera at the origin turned by `yaw`
// (radians, toward +x) from looking along -z.
Vec3 camera_space(const Vec3& p, double yaw) {
  const Vec3 right{std::cos(yaw), 0, std::sin(yaw)}, fwd{std::sin(yaw), 0, -std::cos(yaw)};
  return {dot(p, right), p.y, -dot(p, fwd)};
}

// Closed-form projections of square images: image position of a camera-space direction, or
// false when it has none.
bool perspective_uv(const Vec3& c, double fov, Vec2* uv) {
  if (c.z >= 0) return false;
  const double w = 2 * std::tan(fov / 2);
  *uv = {0.5 + c.x / -c.z / w, 0.5 - c.y / -c.z / w};
  return uv->x >= 0 && uv->x <= 1 && uv->y >= 0 && uv->y <= 1;
}
bool fisheye_uv(const Vec3& c, double fov, Vec2* uv) {  // equidistant, circle inscribed
  const double theta = std::acos(-c.z / length(c)), rho = std::hypot(c.x, c.y);
  const double r = theta / (fov / 2);
  if (r > 1) return false;
  const double a = rho > 0 ? r * c.x / rho : 0, b = rho > 0 ? r * c.y / rho : 0;
  *uv = {0.5 + a / 2, 0.5 - b / 2};
  return true;
}

// The camera at the origin, turning by `yaw_deg` between frames 0 and 1, inside a sphere of
// radius 10: the flow of every pixel is where its direction falls in the turned camera, minus
// where it is.
void check_pan(const std::string& preset, double fov_deg, bool fisheye) {
  const int W = 32, H = 32;
  const double fov = fov_deg * kPi / 180, yaw = 4 * kPi / 180;
  const std::string scene =
      image(W, H) + "[camera]\npreset = \"" + preset + "\"\nfov = " + std::to_string(fov_deg) +
      "\nlook_from = [0, 0, 0]\nlook_at = [0, 0, -1]\n"
      "[[object]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 10\n"
      "[[animate]]\nkey = \"camera.look_at\"\nkeys = [[0, [0, 0, -1]], [1, [" +
      std::to_string(std::sin(yaw)) + ", 0, " + std::to_string(-std::cos(yaw)) + "]]]\n";
  const VisionFrame f = render_frame(scene, {Aov::FlowForward});
  const double turned = std::atan2(std::stod(std::to_string(std::sin(yaw))),
                                   -std::stod(std::to_string(-std::cos(yaw))));
  double worst = 0;
  int valid = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const Vec2 uv{(x + 0.5) / W, (y + 0.5) / H};
      const auto ray = f.scene.camera->generate({uv});
      if (!ray) continue;
      Vec2 next;
      const Vec3 c = camera_space(ray->dir, turned);
      const bool has = fisheye ? fisheye_uv(c, fov, &next) : perspective_uv(c, fov, &next);
      const double fx = f.at("flow_forward", x, y, 0), fy = f.at("flow_forward", x, y, 1);
      SCOPED_TRACE(preset + " pixel " + std::to_string(x) + "," + std::to_string(y));
      ASSERT_EQ(f.at("flow_forward", x, y, 2), has ? 1 : 0) << "valid";
      if (!has) {
        EXPECT_TRUE(std::isnan(fx) && std::isnan(fy));
        continue;
      }
      ++valid;
      const double ex = (next.x - uv.x) * W, ey = (next.y - uv.y) * H;
      EXPECT_NEAR(fx, ex, 1e-4);
      EXPECT_NEAR(fy, ey, 1e-4);
      worst = std::max({worst, std::abs(fx - ex), std::abs(fy - ey)});
    }
  EXPECT_GT(valid, W * H / 2);
  ::testing::Test::RecordProperty(preset + "_worst_px", std::to_string(worst));
  std::printf("%s: worst flow error %.3g px over %d pixels\n", preset.c_str(), worst, valid);
}

TEST(VisionAov, PanFlowEqualsTheClosedFormProjection) {
  check_pan("perspective", 60, false);
  check_pan("fisheye", 180, true);  // pixels turned past 90 degrees have no flow
}

// A sphere of radius 1 at (0, 0, -3) moving by (0.5, 0.2, 0) between frames 0 and 1, seen by a
// still 180-degree equidistant fisheye at the origin, before a still sphere of radius 20.
std::string moving_sphere(int W, int H) {
  return image(W, H) +
         "[camera]\npreset = \"fisheye\"\nfov = 180\nlook_from = [0, 0, 0]\n"
         "look_at = [0, 0, -1]\n"
         "[[object]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 20\n"
         "[[object]]\ntype = \"sphere\"\ncenter = [0, 0, -3]\nradius = 1\n"
         "[[animate]]\nkey = \"object.1.center\"\nkeys = [[0, [0, 0, -3]], [1, [0.5, 0.2, -3]]]\n";
}

// The nearer intersection of the unit ray d from the origin with the sphere (c, r), or -1.
double ray_sphere(const Vec3& d, const Vec3& c, double r) {
  const double b = dot(d, c), disc = b * b - dot(c, c) + r * r;
  return disc < 0 ? -1 : b - std::sqrt(disc);
}

// The flow layer `layer` of frame `frame`: the sphere is at `c` then and moves by `move` to the
// other frame.
void check_moving_sphere(double frame, Aov layer, const Vec3& c, const Vec3& move) {
  const int W = 48, H = 48;
  const double fov = kPi;
  const std::string name = aov_info(layer).name;
  const VisionFrame f = render_frame(moving_sphere(W, H), {layer, Aov::Id}, frame);
  int on_sphere = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const Vec2 uv{(x + 0.5) / W, (y + 0.5) / H};
      const auto ray = f.scene.camera->generate({uv});
      if (!ray) continue;
      const double t = ray_sphere(ray->dir, c, 1);
      // Pixels whose ray grazes the silhouette may hit either sphere in float.
      const double miss = length(c - ray->dir * dot(c, ray->dir));
      if (miss > 0.98 && miss < 1.02) continue;
      SCOPED_TRACE(name + " pixel " + std::to_string(x) + "," + std::to_string(y));
      const double fx = f.at(name, x, y, 0), fy = f.at(name, x, y, 1);
      if (t < 0) {  // the still background: no motion
        EXPECT_EQ(f.at("id", x, y), 0);
        EXPECT_NEAR(fx, 0, 1e-9);
        EXPECT_NEAR(fy, 0, 1e-9);
        continue;
      }
      ++on_sphere;
      EXPECT_EQ(f.at("id", x, y), 1);
      Vec2 there;
      ASSERT_TRUE(fisheye_uv(ray->dir * t + move, fov, &there));
      EXPECT_NEAR(fx, (there.x - uv.x) * W, 1e-4);
      EXPECT_NEAR(fy, (there.y - uv.y) * H, 1e-4);
    }
  EXPECT_GT(on_sphere, 50);
}

TEST(VisionAov, MovingSphereFlowUnderAFisheye) {
  const Vec3 c{0, 0, -3}, move{0.5, 0.2, 0};
  check_moving_sphere(0, Aov::FlowForward, c, move);
  check_moving_sphere(1, Aov::FlowBackward, c + move, -move);
}

// Warping: the surface parameters (uv) of frame 1, read at each pixel's position plus its flow
// (bilinear), give frame 0's, where the point stays in view and its four neighbours at frame 1
// see the moving sphere too.
TEST(VisionAov, WarpingTheNextFrameByTheFlowGivesThisOne) {
  const int W = 128, H = 128;
  const std::string scene = moving_sphere(W, H);
  const VisionFrame now = render_frame(scene, {Aov::FlowForward, Aov::Uv, Aov::Id, Aov::Normal});
  const VisionFrame next = render_frame(scene, {Aov::Uv, Aov::Id}, 1);
  double worst = 0;
  int checked = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      if (now.at("id", x, y) != 1 || now.at("flow_forward", x, y, 2) != 1) continue;
      // Facing the camera (away from the limb, where the point may turn away at frame 1).
      const auto ray = now.scene.camera->generate({{(x + 0.5) / W, (y + 0.5) / H}});
      const Vec3 n{now.at("normal", x, y, 0), now.at("normal", x, y, 1), now.at("normal", x, y, 2)};
      if (!ray || dot(n, ray->dir) > -0.7) continue;
      const double px = x + now.at("flow_forward", x, y, 0),
                   py = y + now.at("flow_forward", x, y, 1);
      const int x0 = int(std::floor(px)), y0 = int(std::floor(py));
      if (x0 < 0 || y0 < 0 || x0 + 1 >= W || y0 + 1 >= H) continue;
      bool same = true;
      double uvs[4][2];
      for (int k = 0; k < 4; ++k) {
        const int xi = x0 + (k & 1), yi = y0 + (k >> 1);
        same = same && next.at("id", xi, yi) == 1;
        for (int c = 0; c < 2; ++c) uvs[k][c] = next.at("uv", xi, yi, c);
      }
      // The sphere's u wraps around once: not across the seam.
      if (!same || std::abs(uvs[0][0] - uvs[3][0]) > 0.2) continue;
      const double ax = px - x0, ay = py - y0;
      for (int c = 0; c < 2; ++c) {
        const double warped = (1 - ay) * ((1 - ax) * uvs[0][c] + ax * uvs[1][c]) +
                              ay * ((1 - ax) * uvs[2][c] + ax * uvs[3][c]);
        const double diff = std::abs(warped - now.at("uv", x, y, c));
        worst = std::max(worst, diff);
        EXPECT_LT(diff, 2e-3) << "pixel " << x << "," << y << " channel " << c << ": warped "
                              << warped << ", this frame " << now.at("uv", x, y, c);
      }
      ++checked;
    }
  EXPECT_GT(checked, 100);
  ::testing::Test::RecordProperty("worst_uv", std::to_string(worst));
  std::printf("worst warped uv difference %.3g over %d pixels\n", worst, checked);
}

}  // namespace
}  // namespace anamorph
