// The vision layers (docs/vision.md): the depth conventions against a plane at a known distance,
// and forward flow against closed-form projections of a panning camera and a moving sphere.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "accel/accel.h"
#include "render/renderer.h"
#include "scene/scene_loader.h"
#include "test_util.h"

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

// ray_origin / ray_direction: the pixel-centre camera ray of every pixel, hits and misses alike,
// whatever the samples (4 stratified a pixel here), and NaN where the camera has no ray.
void check_ray_layers(const std::string& camera, bool corners_without_ray) {
  const int W = 12, H = 10;
  const VisionFrame f = render_frame(
      "[image]\nwidth = 12\nheight = 10\n[render]\nintegrator = \"albedo\"\n"
      "sampler = \"stratified\"\nspp = 4\n" +
          camera + "look_from = [0.5, 0.2, 5]\nlook_at = [0, 0, 0]\n" +
          "[[object]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\n",
      {Aov::RayOrigin, Aov::Distance, Aov::RayDirection});
  int no_ray = 0, misses = 0;
  double worst = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const auto ray = f.scene.camera->generate({{(x + 0.5) / W, (y + 0.5) / H}});
      SCOPED_TRACE(camera + " pixel " + std::to_string(x) + "," + std::to_string(y));
      misses += std::isinf(f.at("distance", x, y));
      for (int c = 0; c < 3; ++c) {
        if (!ray) {
          EXPECT_TRUE(std::isnan(f.at("ray_origin", x, y, c))) << f.at("ray_origin", x, y, c);
          EXPECT_TRUE(std::isnan(f.at("ray_direction", x, y, c)));
          continue;
        }
        EXPECT_NEAR(f.at("ray_origin", x, y, c), ray->org[c], 1e-6);
        EXPECT_NEAR(f.at("ray_direction", x, y, c), ray->dir[c], 1e-6);
        worst = std::max({worst, std::abs(f.at("ray_origin", x, y, c) - ray->org[c]),
                          std::abs(f.at("ray_direction", x, y, c) - ray->dir[c])});
      }
      no_ray += !ray;
    }
  EXPECT_EQ(no_ray > 0, corners_without_ray) << no_ray << " pixels without a ray";
  std::printf("%s: worst ray difference %.3g, %d misses, %d pixels without a ray\n",
              corners_without_ray ? "fisheye" : "perspective", worst, misses, no_ray);
  EXPECT_GT(misses, 20) << "pixels that hit nothing";
}

TEST(VisionAov, RayLayersHoldThePixelCentreRayEverywhere) {
  check_ray_layers("[camera]\npreset = \"perspective\"\nfov = 60\n", false);
  // The inscribed circle of a 12 x 10 image: the corners have no ray.
  check_ray_layers("[camera]\npreset = \"fisheye\"\nfov = 180\n", true);
}

// A number as TOML text that reads back as the same double.
std::string fmt_exact(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
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
      EXPECT_NEAR(fx, ex, 1e-6);  // (the bound; the layer holds floats)
      EXPECT_NEAR(fy, ey, 1e-6);
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

// The dome master of a dome centred on the eye: zenith (up) at the centre, theta from the zenith
// linear in the radius (fov / 2 at the inscribed circle), the front (look_at) toward the bottom
// and the audience's right to the right. Checked against the camera's own rays at frame 0 first.
bool dome_uv(const Vec3& d, const Vec3& front, const Vec3& right, double fov, Vec2* uv) {
  const Vec3 up{0, 1, 0};
  const double r = std::acos(std::clamp(dot(d, up) / length(d), -1.0, 1.0)) / (fov / 2);
  if (r > 1) return false;
  const double xr = dot(d, right), zf = dot(d, front), rho = std::hypot(xr, zf);
  *uv = {0.5 + (rho > 0 ? r / 2 * xr / rho : 0), 0.5 + (rho > 0 ? r / 2 * zf / rho : 0)};
  return true;
}

// A dome turning by yaw about the zenith (the audience turning right): the dome master turns
// about its centre; every pixel's flow is where its direction falls in the turned dome.
TEST(VisionAov, DomePanFlowEqualsTheClosedFormProjection) {
  const int W = 32, H = 32;
  const double fov = kPi, yaw = 4 * kPi / 180;
  const std::string scene =
      image(W, H) +
      "[camera]\npreset = \"dome\"\n"
      "look_from = [0, 0, 0]\nlook_at = [0, 0, -1]\n"
      "[[object]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 10\n"
      "[[animate]]\nkey = \"camera.look_at\"\nkeys = [[0, [0, 0, -1]], [1, [" +
      fmt_exact(std::sin(yaw)) + ", 0, " + fmt_exact(-std::cos(yaw)) + "]]]\n";
  const VisionFrame f = render_frame(scene, {Aov::FlowForward});
  const Vec3 front0{0, 0, -1}, right0{1, 0, 0};
  const Vec3 front1{std::sin(yaw), 0, -std::cos(yaw)}, right1{std::cos(yaw), 0, std::sin(yaw)};
  double worst = 0, worst_self = 0;
  int valid = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const Vec2 uv{(x + 0.5) / W, (y + 0.5) / H};
      const auto ray = f.scene.camera->generate({uv});
      if (!ray) continue;
      Vec2 self, next;
      ASSERT_TRUE(dome_uv(ray->dir, front0, right0, fov, &self)) << x << "," << y;
      worst_self = std::max({worst_self, std::abs(self.x - uv.x), std::abs(self.y - uv.y)});
      const bool has = dome_uv(ray->dir, front1, right1, fov, &next);
      ASSERT_EQ(f.at("flow_forward", x, y, 2), has ? 1 : 0) << "valid at " << x << "," << y;
      if (!has) continue;
      ++valid;
      const double ex = (next.x - uv.x) * W, ey = (next.y - uv.y) * H;
      const double fx = f.at("flow_forward", x, y, 0), fy = f.at("flow_forward", x, y, 1);
      EXPECT_NEAR(fx, ex, 1e-6) << "pixel " << x << "," << y;
      EXPECT_NEAR(fy, ey, 1e-6) << "pixel " << x << "," << y;
      worst = std::max({worst, std::abs(fx - ex), std::abs(fy - ey)});
    }
  EXPECT_LT(worst_self, 1e-9) << "the closed form is not the dome's layout";
  EXPECT_GT(valid, W * H / 2);
  std::printf("dome: worst flow error %.3g px over %d pixels (layout %.3g)\n", worst, valid,
              worst_self);
}

// A full equirectangular panorama turning by yaw toward +x about the up axis: every direction's
// longitude falls by yaw, so every pixel moves left by yaw / 2 pi of the width (wrapping around
// the seam) and not at all vertically.
TEST(VisionAov, EquirectPanFlowIsAShiftOfTheWidth) {
  const int W = 48, H = 24;
  const double yaw_deg = 7.5;
  const double yaw = yaw_deg * kPi / 180;
  const std::string scene =
      image(W, H) +
      "[camera]\npreset = \"equirectangular\"\n"
      "look_from = [0, 0, 0]\nlook_at = [0, 0, -1]\n"
      "[[object]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 10\n"
      "[[animate]]\nkey = \"camera.look_at\"\nkeys = [[0, [0, 0, -1]], [1, [" +
      fmt_exact(std::sin(yaw)) + ", 0, " + fmt_exact(-std::cos(yaw)) + "]]]\n";
  const VisionFrame f = render_frame(scene, {Aov::FlowForward});
  double worst = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const double u = (x + 0.5) / W;
      double u1 = u - yaw / (2 * kPi);
      if (u1 < 0) u1 += 1;
      const double ex = (u1 - u) * W;
      const double fx = f.at("flow_forward", x, y, 0), fy = f.at("flow_forward", x, y, 1);
      EXPECT_EQ(f.at("flow_forward", x, y, 2), 1) << "valid at " << x << "," << y;
      EXPECT_NEAR(fx, ex, 1e-6) << "pixel " << x << "," << y;
      EXPECT_NEAR(fy, 0, 1e-6) << "pixel " << x << "," << y;
      worst = std::max({worst, std::abs(fx - ex), std::abs(fy)});
    }
  std::printf("equirectangular: worst flow error %.3g px over %d pixels\n", worst, W * H);
}

// A rolling shutter (top to bottom over the whole frame: shutter [0, 1]) on a perspective camera
// panning at a constant rate inside a sphere: row v is read at frame F + v, with the camera
// turned by yaw(F + v). A pixel's direction at frame 0, and where frame 1's camera sees it: the
// row v' whose own readout yaw turns the direction onto row v' (solved here by bisection).
TEST(VisionAov, RollingShutterFlowUsesEachPixelsReadoutTime) {
  const int W = 32, H = 32;
  const double fov = 60 * kPi / 180, w = 2 * std::tan(fov / 2), step = 3 * kPi / 180;
  std::string keys;
  double yaw[3];
  for (int k = 0; k < 3; ++k) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "%s[%d, [%.17g, 0, %.17g]]", k ? ", " : "", k,
                  std::sin(k * step), -std::cos(k * step));
    keys += buf;
    yaw[k] = std::atan2(std::sin(k * step), std::cos(k * step));
  }
  const std::string scene = image(W, H) +
                            "[camera]\npreset = \"perspective\"\nfov = 60\n"
                            "rolling_shutter = \"top_to_bottom\"\nshutter = [0, 1]\n"
                            "look_from = [0, 0, 0]\nlook_at = [0, 0, -1]\n"
                            "[[object]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 10\n"
                            "[[animate]]\nkey = \"camera.look_at\"\nkeys = [" +
                            keys + "]\n";
  const VisionFrame f = render_frame(scene, {Aov::FlowForward});
  // The camera's yaw at frame F's readout time t (slerp about y: linear in the angle).
  const auto yaw_at = [&](int F, double t) { return yaw[F] + t * (yaw[F + 1] - yaw[F]); };
  double worst = 0, largest_shift = 0;
  int valid = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const Vec2 uv{(x + 0.5) / W, (y + 0.5) / H};
      const double a = yaw_at(0, uv.y);
      const Vec3 right{std::cos(a), 0, std::sin(a)}, fwd{std::sin(a), 0, -std::cos(a)};
      const Vec3 d = right * ((uv.x - 0.5) * w) + Vec3{0, 1, 0} * (-(uv.y - 0.5) * w) + fwd;
      // Frame 1: the row whose readout sees d there.
      const auto row_error = [&](double v, Vec2* at) {
        return perspective_uv(camera_space(d, yaw_at(1, v)), fov, at) || at->y >= 0 ? at->y - v
                                                                                    : std::nan("");
      };
      double lo = 0, hi = 1;
      Vec2 at;
      const double elo = row_error(lo, &at), ehi = row_error(hi, &at);
      if (!(elo * ehi <= 0)) continue;  // no row sees it
      for (int k = 0; k < 200; ++k) {
        const double mid = 0.5 * (lo + hi);
        (row_error(mid, &at) * elo > 0 ? lo : hi) = mid;
      }
      row_error(0.5 * (lo + hi), &at);
      if (!(at.x >= 0 && at.x <= 1)) continue;
      const double fx = f.at("flow_forward", x, y, 0), fy = f.at("flow_forward", x, y, 1);
      ASSERT_EQ(f.at("flow_forward", x, y, 2), 1) << "pixel " << x << "," << y;
      ++valid;
      const double ex = (at.x - uv.x) * W, ey = (at.y - uv.y) * H;
      EXPECT_NEAR(fx, ex, 1e-5) << "pixel " << x << "," << y;
      EXPECT_NEAR(fy, ey, 1e-5) << "pixel " << x << "," << y;
      worst = std::max({worst, std::abs(fx - ex), std::abs(fy - ey)});
      // How far a global shutter (the whole frame at its open yaw) would be off.
      Vec2 global;
      if (perspective_uv(camera_space(d, yaw[1]), fov, &global))
        largest_shift = std::max(largest_shift, std::abs(global.x - at.x) * W);
    }
  EXPECT_GT(valid, W * H / 2);
  EXPECT_GT(largest_shift, 0.5) << "the readout time matters in this test";
  std::printf(
      "rolling shutter: worst flow error %.3g px over %d pixels (readout shift up to %.3g "
      "px)\n",
      worst, valid, largest_shift);
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
// other frame. Occlusion there, in closed form: a point of the background is hidden when the
// moved sphere lies on its ray; a point of the sphere when it has turned to the sphere's far side
// (its normal away from the camera). Hidden points have no flow (NaN, valid 0).
void check_moving_sphere(double frame, Aov layer, const Vec3& c, const Vec3& move) {
  const int W = 48, H = 48;
  const double fov = kPi;
  const std::string name = aov_info(layer).name;
  const VisionFrame f = render_frame(moving_sphere(W, H), {layer, Aov::Id}, frame);
  int on_sphere = 0, hidden_sphere = 0, hidden_background = 0, background = 0;
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
      const double fx = f.at(name, x, y, 0), fy = f.at(name, x, y, 1), valid = f.at(name, x, y, 2);
      if (t < 0) {  // the still background: no motion, unless the sphere covers it there
        EXPECT_EQ(f.at("id", x, y), 0);
        const double cover = length(c + move - ray->dir * dot(c + move, ray->dir));
        if (cover > 0.98 && cover < 1.02) continue;  // its silhouette there
        if (cover < 1) {
          ++hidden_background;
          EXPECT_EQ(valid, 0) << "covered by the sphere at the other frame";
          EXPECT_TRUE(std::isnan(fx) && std::isnan(fy)) << fx << " " << fy;
          continue;
        }
        ++background;
        EXPECT_EQ(valid, 1);
        EXPECT_NEAR(fx, 0, 1e-9);
        EXPECT_NEAR(fy, 0, 1e-9);
        continue;
      }
      EXPECT_EQ(f.at("id", x, y), 1);
      const Vec3 q = ray->dir * t + move;
      const double facing = dot(q - (c + move), q) / length(q);  // > 0: turned away
      if (std::abs(facing) < 0.02) continue;                     // on the limb there
      if (facing > 0) {
        ++hidden_sphere;
        EXPECT_EQ(valid, 0) << "turned to the sphere's far side";
        continue;
      }
      ++on_sphere;
      EXPECT_EQ(valid, 1);
      Vec2 there;
      ASSERT_TRUE(fisheye_uv(q, fov, &there));
      EXPECT_NEAR(fx, (there.x - uv.x) * W, 1e-4);
      EXPECT_NEAR(fy, (there.y - uv.y) * H, 1e-4);
    }
  EXPECT_GT(on_sphere, 50);
  EXPECT_GT(background, 500);
  EXPECT_GT(hidden_background, 5) << "the moved sphere covers part of the background";
  std::printf("%s: %d sphere pixels with flow, %d hidden; background %d with flow, %d hidden\n",
              name.c_str(), on_sphere, hidden_sphere, background, hidden_background);
}

TEST(VisionAov, MovingSphereFlowUnderAFisheye) {
  const Vec3 c{0, 0, -3}, move{0.5, 0.2, 0};
  check_moving_sphere(0, Aov::FlowForward, c, move);
  check_moving_sphere(1, Aov::FlowBackward, c + move, -move);
}

// The motion layer is the flows in Cycles' convention (y up; previous - now, now - next) where
// they are valid, and keeps the motion of points hidden at the other frame (the still
// background behind the moved sphere: 0).
TEST(VisionAov, MotionLayerIsTheFlowsInCyclesConvention) {
  const int W = 48, H = 48;
  for (const double frame : {0.0, 1.0}) {
    const VisionFrame f = render_frame(
        moving_sphere(W, H), {Aov::Motion, Aov::FlowForward, Aov::FlowBackward, Aov::Id}, frame);
    int both = 0, hidden = 0;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        if (f.at("id", x, y) < 0) {
          for (int c = 0; c < 4; ++c) EXPECT_EQ(f.at("motion", x, y, c), 0) << "no hit";
          continue;
        }
        SCOPED_TRACE("frame " + std::to_string(frame) + " pixel " + std::to_string(x) + "," +
                     std::to_string(y));
        const bool fv = f.at("flow_forward", x, y, 2) == 1,
                   bv = f.at("flow_backward", x, y, 2) == 1;
        if (!fv || !bv) {
          hidden += f.at("id", x, y) == 0;
          for (int c = 0; c < 4; ++c) EXPECT_TRUE(std::isfinite(f.at("motion", x, y, c)));
          if (f.at("id", x, y) == 0) {
            for (int c = 0; c < 4; ++c) EXPECT_NEAR(f.at("motion", x, y, c), 0, 1e-9) << "still";
          }
          continue;
        }
        ++both;
        EXPECT_EQ(f.at("motion", x, y, 0), f.at("flow_backward", x, y, 0));
        EXPECT_EQ(f.at("motion", x, y, 1), -f.at("flow_backward", x, y, 1));
        EXPECT_EQ(f.at("motion", x, y, 2), -f.at("flow_forward", x, y, 0));
        EXPECT_EQ(f.at("motion", x, y, 3), f.at("flow_forward", x, y, 1));
      }
    EXPECT_GT(both, 1000);
    EXPECT_GT(hidden, 5);
  }
}

// Warping: the surface parameters (uv) of frame `to`, read at each pixel of frame `from` plus its
// flow (bilinear), give `from`'s, where the pixel has flow, faces the camera, and the four
// neighbours at `to` see the same object. The pixels without flow are those the moving sphere
// covers at `to` (give or take a pixel at its silhouette).
void check_warp(const VisionFrame& from, const VisionFrame& to, const std::string& layer) {
  const int W = from.out.width, H = from.out.height;
  double worst = 0;
  int checked = 0, hidden = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const double id = from.at("id", x, y);
      if (id < 0) continue;  // outside the fisheye's circle
      if (from.at(layer, x, y, 2) != 1) {
        bool covered = false;  // the sphere at `to`, here or next to here
        for (int k = 0; k < 9; ++k) {
          const int xi = std::clamp(x + k % 3 - 1, 0, W - 1),
                    yi = std::clamp(y + k / 3 - 1, 0, H - 1);
          covered = covered || to.at("id", xi, yi) == 1;
        }
        EXPECT_TRUE(covered) << layer << " pixel " << x << "," << y << " (id " << id
                             << ") has no flow but nothing covers it";
        hidden += id == 0;
        continue;
      }
      // Facing the camera (away from the limb, where the point may turn away at frame 1).
      const auto ray = from.scene.camera->generate({{(x + 0.5) / W, (y + 0.5) / H}});
      const Vec3 n{from.at("normal", x, y, 0), from.at("normal", x, y, 1),
                   from.at("normal", x, y, 2)};
      if (!ray || dot(n, ray->dir) > -0.7) continue;
      const double px = x + from.at(layer, x, y, 0), py = y + from.at(layer, x, y, 1);
      const int x0 = int(std::floor(px)), y0 = int(std::floor(py));
      if (x0 < 0 || y0 < 0 || x0 + 1 >= W || y0 + 1 >= H) continue;
      bool same = true;
      double uvs[4][2];
      for (int k = 0; k < 4; ++k) {
        const int xi = x0 + (k & 1), yi = y0 + (k >> 1);
        same = same && to.at("id", xi, yi) == id;
        for (int c = 0; c < 2; ++c) uvs[k][c] = to.at("uv", xi, yi, c);
      }
      // The spheres' u wraps around once: not across the seam.
      if (!same || std::abs(uvs[0][0] - uvs[3][0]) > 0.2) continue;
      const double ax = px - x0, ay = py - y0;
      for (int c = 0; c < 2; ++c) {
        const double warped = (1 - ay) * ((1 - ax) * uvs[0][c] + ax * uvs[1][c]) +
                              ay * ((1 - ax) * uvs[2][c] + ax * uvs[3][c]);
        const double diff = std::abs(warped - from.at("uv", x, y, c));
        worst = std::max(worst, diff);
        EXPECT_LT(diff, 2e-3) << layer << " pixel " << x << "," << y << " channel " << c
                              << ": warped " << warped << ", this frame " << from.at("uv", x, y, c);
      }
      ++checked;
    }
  EXPECT_GT(checked, 1000) << layer;
  EXPECT_GT(hidden, 50) << layer << ": background pixels the sphere covers at the other frame";
  ::testing::Test::RecordProperty(layer + "_worst_uv", std::to_string(worst));
  std::printf("%s: worst warped uv difference %.3g over %d pixels; %d background pixels hidden\n",
              layer.c_str(), worst, checked, hidden);
}

// Frame 1 warped by frame 0's forward flow gives frame 0; frame 0 warped by frame 1's backward
// flow gives frame 1. The moving sphere passes in front of the still background sphere.
TEST(VisionAov, WarpingTheOtherFrameByTheFlowGivesThisOne) {
  const int W = 128, H = 128;
  const std::string scene = moving_sphere(W, H);
  const std::vector<Aov> aovs{Aov::FlowForward, Aov::FlowBackward, Aov::Uv, Aov::Id, Aov::Normal};
  const VisionFrame f0 = render_frame(scene, aovs), f1 = render_frame(scene, aovs, 1);
  check_warp(f0, f1, "flow_forward");
  check_warp(f1, f0, "flow_backward");
}

// The triangle `hit` lies on, in world space, as `accel` holds it (flattened or instanced).
void world_triangle(const Accel& accel, const Hit& hit, Vec3 p[3]) {
  const Accel::Record& r = accel.record(hit.object_id);
  const bool flat = r.kind == Accel::Record::Kind::FlatMesh;
  const TriangleMesh& m = flat ? *r.mesh : r.proto->meshes[hit.mesh];
  for (int k = 0; k < 3; ++k) {
    const Vec3 v(m.positions[m.indices[size_t(hit.prim) * 3 + size_t(k)]]);
    p[k] = flat ? v : r.world_from_object.point(v);
  }
}

// skinned_morph.glb (a tube skinned to a bending bone chain, a sphere with animated morph
// targets; tests/data/gltf/blender): each pixel's forward flow is where the point, the same
// barycentric combination of its triangle's vertices as deformed at frame + 1, is seen then, found
// here from the two frames' own acceleration structures and Camera::project.
TEST(VisionAov, DeformingMeshFlowFollowsTheVertices) {
  const int W = 32, H = 24;  // (each pixel projects through the glTF camera: seconds under ASan)
  const std::string toml = image(W, H) +
                           "[camera]\ngltf_camera = 0\n[[object]]\ntype = \"mesh\"\nfile = \"" +
                           (test::data_dir() / "gltf/blender/skinned_morph.glb").string() + "\"\n";
  // Two loads (frame 6 and 7; the glTF's isolated loader is slow under sanitizers): frame 7's
  // scene serves both the render's flow and the check.
  VisionFrame f{load_scene_from_string(toml, "vision.toml", {}, 6), {}};
  f.scene.next = frame_motion(load_scene_from_string(toml, "vision.toml", {}, 7));
  const Renderer renderer(f.scene);
  Film film(W, H, {Aov::FlowForward});
  RenderOptions opt;
  opt.aovs = {Aov::FlowForward};
  renderer.render(film, opt);
  f.out = film.output();
  const Scene& next = *f.scene.next->geometry;
  const Camera& next_camera = *f.scene.next->camera;
  const Accel here(f.scene), there(next);
  int compared = 0;
  double worst = 0, deformation = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const Vec2 uv{(x + 0.5) / W, (y + 0.5) / H};
      const auto ray = f.scene.camera->generate({uv});
      Hit h;
      if (!ray || !here.intersect(Ray{ray->org, ray->dir, 0, kInf}, &h)) continue;
      if (f.at("flow_forward", x, y, 2) != 1) continue;  // (hidden at frame + 1)
      Vec3 a[3], b[3];
      world_triangle(here, h, a);
      world_triangle(there, h, b);
      // Barycentric coordinates of the hit in its triangle now, applied to the vertices then.
      const Vec3 e1 = a[1] - a[0], e2 = a[2] - a[0], q = h.p - a[0];
      const double d00 = dot(e1, e1), d01 = dot(e1, e2), d11 = dot(e2, e2);
      const double den = d00 * d11 - d01 * d01;
      const double v = (d11 * dot(q, e1) - d01 * dot(q, e2)) / den,
                   w = (d00 * dot(q, e2) - d01 * dot(q, e1)) / den;
      const Vec3 moved = b[0] * (1 - v - w) + b[1] * v + b[2] * w;
      const std::vector<Vec2> seen = next_camera.project(moved);
      ASSERT_FALSE(seen.empty()) << "pixel " << x << "," << y << " has flow, no projection";
      const Vec2 flow{(seen[0].x - uv.x) * W, (seen[0].y - uv.y) * H};
      const double fx = f.at("flow_forward", x, y, 0), fy = f.at("flow_forward", x, y, 1);
      EXPECT_NEAR(fx, flow.x, 1e-5) << "pixel " << x << "," << y;
      EXPECT_NEAR(fy, flow.y, 1e-5) << "pixel " << x << "," << y;
      worst = std::max({worst, std::abs(fx - flow.x), std::abs(fy - flow.y)});
      // How far the vertices move the point beyond its instance's transform.
      const Accel::Record& r = here.record(h.object_id);
      const Transform rigid = next.instances[r.source].world_from_object *
                              f.scene.instances[r.source].world_from_object.inverse();
      deformation = std::max(deformation, length(moved - rigid.point(h.p)));
      ++compared;
    }
  EXPECT_GT(compared, 200);
  EXPECT_GT(deformation, 1e-2) << "the meshes do not deform between the frames";
  std::printf(
      "deforming meshes: %d pixels, worst flow difference %.3g px (vertex motion up to "
      "%.3g units beyond the instances' transforms)\n",
      compared, worst, deformation);
}

}  // namespace
}  // namespace anamorph
