// Source projections (camera/source_projection.h) and STMaps (camera/stmap.h): each source kind
// against the camera preset that renders that layout, round trips, the identity map, the
// central-camera check, forward o inverse = identity and alpha where there is no ray.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "camera/coins.h"
#include "camera/source_projection.h"
#include "camera/stmap.h"
#include "params/params.h"
#include "preset_test_util.h"

namespace anamorph {
namespace {

using test::str;

struct SourceCase {
  std::string spec;    // --source
  std::string preset;  // the preset that renders the same layout at its default look_at
  std::string toml;
  ImageInfo img;
};

const SourceCase kCases[] = {
    {"equirect", "equirectangular", "", {64, 32}},
    {"cubemap", "cubemap", "", {48, 32}},
    {"cubemap:6x1:opengl", "cubemap", "layout = \"6x1\"\nconvention = \"opengl\"", {96, 16}},
    {"fisheye:180", "fisheye", "fov = 180", {40, 40}},
    {"fisheye:220:1.5", "fisheye", "fov = 220", {60, 40}},
    {"perspective:90", "perspective", "fov = 90", {40, 40}},
    {"perspective:60:2", "perspective", "fov = 60", {80, 40}},
};

// The source's direction at every sample of a grid is the preset's ray there, and the source
// maps it back to the same position.
TEST(SourceProjection, MatchesThePresetOfTheSameLayoutAndRoundTrips) {
  for (const SourceCase& c : kCases) {
    const auto source = make_source_projection(c.spec);
    EXPECT_NEAR(source->aspect(), double(c.img.width) / c.img.height, 1e-12) << c.spec;
    const VirtualCamera cam = test::camera(c.preset, c.toml, c.img);
    int compared = 0;
    for (int j = 0; j < 23; ++j)
      for (int i = 0; i < 23; ++i) {
        const Vec2 uv{(i + 0.37) / 23, (j + 0.61) / 23};
        const auto d = source->to_direction(uv);
        const auto r = test::ray(cam, uv);
        ASSERT_EQ(bool(d), bool(r)) << c.spec << " at " << str(uv);
        if (!d) continue;
        ++compared;
        EXPECT_LT(test::angle_deg(*d, r->dir), 1e-9)
            << c.spec << " at " << str(uv) << ": " << str(*d) << " vs preset " << str(r->dir);
        const auto back = source->to_image(*d);
        ASSERT_TRUE(back) << c.spec << " at " << str(uv);
        EXPECT_LT(length(*back - uv), 1e-12) << c.spec << ": " << str(uv) << " -> " << str(*back);
      }
    EXPECT_GT(compared, 200) << c.spec;
  }
}

TEST(SourceProjection, BadSpecsNameTheProblem) {
  const auto message = [](const std::string& spec) {
    try {
      make_source_projection(spec);
    } catch (const ParamError& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  EXPECT_NE(message("mercator").find("valid: equirect, cubemap"), std::string::npos)
      << message("mercator");
  EXPECT_NE(message("fisheye").find("fisheye:FOV"), std::string::npos) << message("fisheye");
  EXPECT_NE(message("fisheye:abc").find("\"abc\""), std::string::npos) << message("fisheye:abc");
  EXPECT_NE(message("fisheye:400").find("[0.001, 360]"), std::string::npos)
      << message("fisheye:400");
  EXPECT_NE(message("perspective:180").find("perspective FOV"), std::string::npos);
  EXPECT_NE(message("cubemap:4x3").find("4x3"), std::string::npos);
  EXPECT_NE(message("equirect:2").find("no arguments"), std::string::npos);
}

// An equirect camera mapped to an equirect source is the identity: s = (x + 0.5) / W and
// t = 1 - (y + 0.5) / H (from the bottom), alpha 1, direction the ray's.
TEST(StMap, EquirectToEquirectIsTheIdentity) {
  const VirtualCamera cam = test::camera("equirectangular", "", {64, 32});
  const StMap m = forward_stmap(cam, *make_source_projection("equirect"), 64, 32);
  double worst = 0;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 64; ++x) {
      const size_t i = size_t(y) * 64 + size_t(x);
      ASSERT_EQ(m.alpha[i], 1.0f) << x << "," << y;
      worst = std::max({worst, std::abs(m.st[2 * i] - (x + 0.5) / 64),
                        std::abs(m.st[2 * i + 1] - (1 - (y + 0.5) / 32))});
    }
  EXPECT_LT(worst, 1e-6) << "largest |st - pixel center| of the identity map";
}

// A perspective camera's center pixel maps to where the source shows its view direction
// (a rotated rig: the direction is not an axis).
TEST(StMap, PerspectiveCenterMapsToItsViewDirection) {
  const VirtualCamera cam = test::camera(
      "perspective", "look_from = [0, 0, 0]\nlook_at = [1, 0.5, -2]\nfov = 40", {41, 41});
  for (const char* spec : {"equirect", "fisheye:200", "cubemap"}) {
    const auto source = make_source_projection(spec);
    const StMap m = forward_stmap(cam, *source, 41, 41);
    const size_t c = 20 * 41 + 20;
    const auto want = source->to_image(normalize(Vec3{1, 0.5, -2}));
    ASSERT_TRUE(want && m.alpha[c] == 1.0f) << spec;
    EXPECT_NEAR(m.st[2 * c], want->x, 1e-6) << spec;
    EXPECT_NEAR(m.st[2 * c + 1], 1 - want->y, 1e-6) << spec;
    const Vec3 d{m.direction[3 * c], m.direction[3 * c + 1], m.direction[3 * c + 2]};
    EXPECT_LT(test::angle_deg(d, normalize(Vec3{1, 0.5, -2})), 1e-5) << str(d);
  }
}

// Outside a fisheye's image circle the camera has no ray: alpha 0 and st 0 there; inside, 1.
TEST(StMap, AlphaIsZeroWhereTheCameraHasNoRay) {
  const VirtualCamera cam = test::camera("fisheye", "fov = 180", {48, 32});
  const StMap m = forward_stmap(cam, *make_source_projection("equirect"), 48, 32);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 48; ++x) {
      const size_t i = size_t(y) * 48 + size_t(x);
      const bool ray = bool(test::ray(cam, {(x + 0.5) / 48, (y + 0.5) / 32}));
      EXPECT_EQ(m.alpha[i], ray ? 1.0f : 0.0f) << x << "," << y;
      if (!ray) {
        EXPECT_EQ(m.st[2 * i] + m.st[2 * i + 1], 0.0f) << x << "," << y;
      }
    }
  EXPECT_EQ(m.alpha[0], 0.0f) << "the corner is outside the circle";
}

// For every source pixel the inverse map gives a camera position; the camera's ray there shows
// the source pixel's center again (forward o inverse) to 1e-3 source pixels. Cameras with a
// closed-form inverse (dome with tilt, panini) and one with coins (the numeric inverse).
TEST(StMap, ForwardOfInverseIsTheIdentity) {
  struct Cam {
    std::string preset, toml, coin;
  };
  const Cam cams[] = {
      {"fisheye", "fov = 180\nlook_at = [0.3, 1, -1]", ""},
      {"dome", "fov = 180\ntilt = 30", ""},
      {"panini", "fov = 120", ""},
      {"fisheye", "fov = 160",
       "position = [0.5, 0.2, -3]\nradius = 0.3\nstrength = 0.6\naffects = \"dir\""},
  };
  const int SW = 48, SH = 24, W = 32, H = 32;
  const auto source = make_source_projection("equirect");
  for (const Cam& c : cams) {
    SCOPED_TRACE(c.preset + " {" + c.toml + "} coin {" + c.coin + "}");
    VirtualCameraParts parts = make_preset(c.preset, c.toml, {W, H});
    if (!c.coin.empty()) parts.coins.push_back(make_coin(c.coin));
    const VirtualCamera cam(std::move(parts));
    const StMap inv = inverse_stmap(cam, map_sphere(cam, W, H), *source, SW, SH);
    int defined = 0;
    double worst = 0;
    for (int y = 0; y < SH; ++y)
      for (int x = 0; x < SW; ++x) {
        const size_t i = size_t(y) * SW + size_t(x);
        if (inv.alpha[i] == 0) continue;
        ++defined;
        const Vec2 uv{inv.st[2 * i], 1 - double(inv.st[2 * i + 1])};
        const auto r = test::ray(cam, uv);
        ASSERT_TRUE(r) << "no ray at the inverse's " << str(uv);
        const auto back = source->to_image(r->dir);
        ASSERT_TRUE(back);
        Vec2 px{back->x * SW - (x + 0.5), back->y * SH - (y + 0.5)};
        px.x -= SW * std::round(px.x / SW);
        worst = std::max(worst, length(px));
      }
    EXPECT_GT(defined, SW * SH / 8);
    // (The map stores positions as floats: 6e-8 of W = 32 pixels is 2e-6 px.)
    EXPECT_LT(worst, 1e-3) << "largest |forward(inverse(p)) - p| in source pixels";
  }
}

// Only central cameras are reprojections of directions.
TEST(StMap, NonCentralCamerasAreRefused) {
  const VirtualCamera ortho = test::camera("orthographic", "view_width = 2", {16, 16});
  try {
    central_origin(ortho, 16, 16);
    ADD_FAILURE() << "an orthographic camera was taken for central";
  } catch (const NonCentralCamera& e) {
    EXPECT_NE(std::string(e.what()).find("not central"), std::string::npos) << e.what();
  }
  const VirtualCamera fish = test::camera("fisheye", "look_from = [1, 2, 3]", {16, 16});
  const Vec3 o = central_origin(fish, 16, 16);
  EXPECT_LT(length(o - Vec3{1, 2, 3}), 1e-12) << str(o);
}

// A non-central camera through a sphere of radius D about its mean origin: an orthographic
// camera's ray from (x, y, 0) along -z leaves the sphere at (x, y, -sqrt(D^2 - x^2 - y^2)), seen
// from the centre in that direction; the differentials are those of the carried direction; and
// forward o inverse is the identity.
TEST(StMap, ANonCentralCameraMapsThroughASphereAtTheGivenDepth) {
  const int W = 24, H = 16;
  const VirtualCamera ortho = test::camera("orthographic", "view_width = 3", {W, H});
  const double D = 2.5;
  const DepthSphere sphere = map_sphere(ortho, W, H, D);
  EXPECT_LT(length(sphere.eye), 1e-12) << str(sphere.eye);
  const auto source = make_source_projection("equirect");
  const StMap m = forward_stmap(ortho, *source, W, H, sphere);
  double worst = 0, worst_d = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const Vec2 uv{(x + 0.5) / W, (y + 0.5) / H};
      const auto r = test::ray(ortho, uv);
      ASSERT_TRUE(r);
      const Vec3 o = r->org;
      const Vec3 want = Vec3{o.x, o.y, -std::sqrt(D * D - o.x * o.x - o.y * o.y)} / D;
      const auto st = source->to_image(want);
      ASSERT_TRUE(st);
      const size_t i = size_t(y) * W + size_t(x);
      ASSERT_EQ(m.alpha[i], 1.0f);
      worst = std::max(worst, std::hypot(m.st[2 * i] - st->x, m.st[2 * i + 1] - (1 - st->y)));
      // d(direction)/du against a central difference of the carried directions.
      const double h = 1e-6;
      const auto at = [&](double du) {
        return seen_from_eye(*test::ray(ortho, {uv.x + du, uv.y}), sphere)->dir;
      };
      const Vec3 fd = (at(h) - at(-h)) / (2 * h);
      worst_d = std::max(worst_d, length(seen_from_eye(*r, sphere)->ddir_du - fd));
    }
  EXPECT_LT(worst, 1e-6) << "largest st difference from the closed form";
  EXPECT_LT(worst_d, 1e-5) << "largest ddir_du difference from finite differences";
  // The inverse: each defined source pixel's camera position carries back to that pixel.
  const int SW = 64, SH = 32;
  const StMap inv = inverse_stmap(ortho, sphere, *source, SW, SH);
  int defined = 0;
  double back_worst = 0;
  for (int y = 0; y < SH; ++y)
    for (int x = 0; x < SW; ++x) {
      const size_t i = size_t(y) * SW + size_t(x);
      if (inv.alpha[i] == 0) continue;
      ++defined;
      const auto r = test::ray(ortho, {inv.st[2 * i], 1 - double(inv.st[2 * i + 1])});
      ASSERT_TRUE(r);
      const auto back = source->to_image(seen_from_eye(*r, sphere)->dir);
      ASSERT_TRUE(back);
      back_worst =
          std::max(back_worst, std::hypot(back->x * SW - (x + 0.5), back->y * SH - (y + 0.5)));
    }
  EXPECT_GT(defined, 8) << "source pixels that the orthographic view covers";
  EXPECT_LT(back_worst, 1e-3) << "largest |forward(inverse(p)) - p| in source pixels";
}

}  // namespace
}  // namespace anamorph
