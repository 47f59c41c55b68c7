// The camera's views for the editor: the magnification map (/api/magnification), the coins'
// image positions (/api/coins), the ray overview (/api/rays) and the animation frame shown
// (/api/time), each checked against the camera's own geometry computed here.
#include "server_fixture.h"

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numbers>

#include <fmt/format.h>

namespace anamorph::test {
namespace {

using V3 = std::array<double, 3>;

constexpr double kPi = std::numbers::pi;

V3 sub(const V3& a, const V3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
V3 add(const V3& a, const V3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
V3 mul(const V3& a, double k) { return {a[0] * k, a[1] * k, a[2] * k}; }
double dot(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
V3 cross(const V3& a, const V3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double norm(const V3& a) { return std::sqrt(dot(a, a)); }
V3 unit(const V3& a) { return mul(a, 1 / norm(a)); }
// The angle between two vectors (accurate for small angles too).
double angle(const V3& a, const V3& b) { return std::atan2(norm(cross(a, b)), dot(a, b)); }
V3 v3(const json& j) { return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()}; }
std::string str(const V3& a) { return fmt::format("[{}, {}, {}]", a[0], a[1], a[2]); }

// The unit world direction of a perspective camera (preset "perspective", fov_axis horizontal, no
// lens shift, up = +y) through image position (u, v) of a w x h image: the image plane at
// distance 1 spans 2 tan(fov / 2) across the width, u to the right, v down (preset_perspective.cpp
// and Transform::look_at).
V3 perspective_dir(const V3& from, const V3& at, double fov_deg, double aspect, double u,
                   double v) {
  const V3 f = unit(sub(at, from));
  const V3 r = unit(cross(f, {0, 1, 0}));
  const V3 up = cross(r, f);
  const double hw = std::tan(fov_deg * kPi / 360), hh = hw / aspect;
  const double x = (2 * u - 1) * hw, y = -(2 * v - 1) * hh;
  return unit(add(add(mul(r, x), mul(up, y)), f));
}

// The float32 little-endian values of a magnification map.
std::vector<float> floats(const std::string& body) {
  std::vector<float> m(body.size() / 4);
  for (size_t i = 0; i < m.size(); ++i) {
    uint32_t bits = 0;
    for (int b = 0; b < 4; ++b)
      bits |= uint32_t(static_cast<unsigned char>(body[4 * i + b])) << (8 * b);
    m[i] = std::bit_cast<float>(bits);
  }
  return m;
}

// `text` with its first `a` replaced by `b` (which must be there).
std::string replaced(std::string text, const std::string& a, const std::string& b) {
  const size_t at = text.find(a);
  if (at == std::string::npos) throw std::logic_error("no '" + a + "' in the scene");
  return text.replace(at, a.size(), b);
}

// kScene through a 180 degree fisheye on a 64 x 32 image: the circle fits the height, so left
// and right of it (and in the corners) there is no ray.
std::string fisheye_scene() {
  std::string text = replaced(kScene, "preset = \"perspective\"", "preset = \"fisheye\"");
  text = replaced(text, "fov = 50", "fov = 180");
  return replaced(text, "height = 48", "height = 32");
}

// A perspective camera at z = 5 looking down -z at the infinite plane z = 0 facing it.
std::string plane_scene(int w, int h, double fov) {
  return fmt::format(R"([image]
width = {}
height = {}

[render]
integrator = "whitted"
spp = 1

[camera]
preset = "perspective"
look_from = [0.0, 0.0, 5.0]
look_at = [0.0, 0.0, 0.0]
fov = {}

[[object]]
type = "plane"
point = [0.0, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]

[[light]]
type = "point"
position = [0.0, 0.0, 4.0]
intensity = [10, 10, 10]
)",
                     w, h, fov);
}

class Magnification {
 public:
  Magnification(std::vector<float> m, int w, int h) : m_(std::move(m)), w_(w), h_(h) {}
  float at(int x, int y) const { return m_[size_t(y) * w_ + x]; }
  // The pixel whose center is nearest (u, v).
  float nearest(double u, double v, int* px = nullptr, int* py = nullptr) const {
    const int x = std::clamp(int(std::floor(u * w_)), 0, w_ - 1);
    const int y = std::clamp(int(std::floor(v * h_)), 0, h_ - 1);
    if (px) *px = x;
    if (py) *py = y;
    return at(x, y);
  }
  const std::vector<float>& values() const { return m_; }

 private:
  std::vector<float> m_;
  int w_, h_;
};

class CameraApi : public ServerTest {
 protected:
  // GET /api/magnification for document version `v`; fails the test unless it is 200 with
  // w * h floats.
  Magnification magnification(int w, int h, int64_t v) {
    const Reply r = get(fmt::format("/api/magnification?width={}&height={}&version={}", w, h, v));
    EXPECT_EQ(r.status, 200) << r.body.substr(0, 300);
    EXPECT_EQ(r.header("content-type"), "application/octet-stream");
    EXPECT_EQ(r.body.size(), size_t(w) * h * 4) << w << " x " << h;
    std::vector<float> m = floats(r.body);
    m.resize(size_t(w) * h, std::nanf(""));
    return {std::move(m), w, h};
  }
  json coins(int64_t v) {
    const Reply r = get("/api/coins?version=" + std::to_string(v));
    EXPECT_EQ(r.status, 200) << r.body;
    return body_of(r);
  }
  json rays(const std::string& query) {
    const Reply r = get("/api/rays?" + query);
    EXPECT_EQ(r.status, 200) << query << ": " << r.body.substr(0, 300);
    return body_of(r);
  }
  // The version after an edit that must succeed.
  int64_t edited(const std::string& key, const json& value) {
    const Reply e = edit(key, value, version());
    EXPECT_EQ(e.status, 200) << key << " = " << value.dump() << ": " << e.body;
    return body_of(e).value("version", int64_t(-1));
  }
};

// ---- /api/magnification -------------------------------------------------------------------------

TEST_F(CameraApi, MagnificationWithoutCoinsIsPositiveAndFinite) {
  // The default scene: rays meet the sphere, the floor or nothing (the footprint one unit away),
  // so the footprints differ a lot, but every pixel has a ray and a finite, positive scale.
  const int w = 40, h = 30;
  const Magnification m = magnification(w, h, version());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      ASSERT_TRUE(std::isfinite(m.at(x, y)) && m.at(x, y) > 0)
          << "pixel (" << x << ", " << y << "): " << m.at(x, y);
}

TEST_F(CameraApi, MagnificationOfAPinholeOnAFacingPlaneIsItsCosineLaw) {
  // A pinhole at distance D from a plane facing it: a pixel at angle theta from the axis sees its
  // solid angle wh cos^3(theta) at the distance D / cos(theta), a footprint of D^2 wh cos(theta).
  // Without coins the map is sqrt(mean footprint / footprint) = sqrt(mean(cos) / cos(theta)).
  // With a 20 degree field every value is within 2 % of 1.
  start(dir.write("plane.toml", plane_scene(64, 48, 20)));
  const int w = 33, h = 25;
  const Magnification m = magnification(w, h, version());
  const double hw = std::tan(20 * kPi / 360), hh = hw * 48 / 64;
  auto cos_at = [&](int x, int y) {
    const double a = (2 * (x + 0.5) / w - 1) * hw, b = (2 * (y + 0.5) / h - 1) * hh;
    return 1 / std::sqrt(1 + a * a + b * b);
  };
  double mean_cos = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) mean_cos += cos_at(x, y) / (w * h);
  double lo = 1e9, hi = -1e9;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double got = m.at(x, y), want = std::sqrt(mean_cos / cos_at(x, y));
      ASSERT_TRUE(std::isfinite(got) && got > 0) << "pixel (" << x << ", " << y << "): " << got;
      EXPECT_NEAR(got, 1.0, 0.02) << "pixel (" << x << ", " << y << ")";
      // (float32 values; the hit distances and derivatives are exact up to rounding)
      EXPECT_NEAR(got, want, 1e-5) << "pixel (" << x << ", " << y << ")";
      lo = std::min(lo, got);
      hi = std::max(hi, got);
    }
  // The beam's cross-section is widest on the axis (cos = 1), so the center reduces slightly and
  // the corners magnify.
  EXPECT_LT(m.at(w / 2, h / 2), 1.0);
  EXPECT_GT(m.at(0, 0), 1.0);
  EXPECT_GT(hi - lo, 1e-3) << "the map is flat: " << lo << " .. " << hi;
}

TEST_F(CameraApi, DirCoinZoomsByOneOverOneMinusStrengthAtItsCenter) {
  // An `affects = "dir"` coin of strength m on a pinhole: at (uc, vc) the directions turn toward
  // the coin a fraction m of the way, so angles around it (and lengths on the surface it sits on)
  // scale by 1 - m in both image directions (docs/coins.md, Magnification: across by 1 / (1 - w),
  // along by 1 / (1 - w - r w'), w' = 0 at the center). The map is linear (sqrt of the footprint
  // ratio against the same camera without the coin): 1 / (1 - m) = 2 for m = 0.5.
  start(dir.write("plane.toml", plane_scene(64, 48, 50)));
  const int64_t v = edited(
      "camera.coin",
      json::array({json{
          {"position", {0.0, 0.0, 0.0}}, {"strength", 0.5}, {"radius", 0.2}, {"affects", "dir"}}}));
  const json sites = coins(v)["sites"];
  ASSERT_EQ(sites.size(), 1u) << sites.dump();
  const double uc = sites[0]["uv"][0], vc = sites[0]["uv"][1];
  EXPECT_NEAR(uc, 0.5, 1e-9) << sites.dump();
  EXPECT_NEAR(vc, 0.5, 1e-9) << sites.dump();
  // An odd size puts a pixel center exactly at (0.5, 0.5): the value there is the analytic zoom
  // up to float32 rounding.
  const int w = 65, h = 49;
  const Magnification m = magnification(w, h, v);
  int px = -1, py = -1;
  const float center = m.nearest(uc, vc, &px, &py);
  EXPECT_EQ(px, w / 2);
  EXPECT_EQ(py, h / 2);
  EXPECT_NEAR(center, 2.0, 1e-5) << "at pixel (" << px << ", " << py << ")";
  // Outside the radius every ray is the coin-less camera's, bit for bit: exactly 1.
  for (const auto& [x, y] : {std::pair{0, 0}, {w - 1, 0}, {0, h - 1}, {w - 1, h - 1}}) {
    const double du = (x + 0.5) / w - uc, dv = (y + 0.5) / h - vc;
    ASSERT_GT(std::hypot(du, dv), 0.2) << "pixel (" << x << ", " << y << ") is inside the radius";
    EXPECT_NEAR(m.at(x, y), 1.0, 1e-6) << "corner pixel (" << x << ", " << y << ")";
  }
  // Inside the radius the map magnifies near the center and shrinks in a ring before the rim
  // (docs/coins.md); the center is the maximum.
  for (float x : m.values()) EXPECT_LE(x, center + 1e-5);
}

TEST_F(CameraApi, OffCenterDirCoinZoomsAtItsImagePosition) {
  // The same zoom where the coin sits off the axis, on the plane z = 0. (uc, vc) is no pixel
  // center now: the nearest center of a 1024 x 768 map is within d <= 0.5 hypot(1/1024, 1/768)
  // = 8.1e-4 of it, x = (d / R)^2 <= 1.7e-5. Near the center the smooth kernel gives
  // w = m (1 - 3x), so the zoom across (1 / (1 - w)) and along (1 / (1 - w - r w')) the radius
  // has the geometric mean 1 / (1 - m) * (1 - 6 m x / (1 - m)) = 2 (1 - 6x): 2.0e-4 below 2 at
  // most (measured: 9.8e-5). The bent ray also meets the plane at a slightly different distance,
  // an effect of the same order. The tolerance 1e-3 is 5 times the bound.
  start(dir.write("plane.toml", plane_scene(64, 48, 50)));
  const V3 coin{0.9, 0.5, 0.0};
  const Reply p = post("/api/project", json{{"position", coin}, {"version", version()}});
  ASSERT_EQ(p.status, 200) << p.body;
  const json uvs = body_of(p)["uv"];
  ASSERT_EQ(uvs.size(), 1u) << p.body;
  const int64_t v = edited(
      "camera.coin",
      json::array(
          {json{{"position", coin}, {"strength", 0.5}, {"radius", 0.2}, {"affects", "dir"}}}));
  const json sites = coins(v)["sites"];
  ASSERT_EQ(sites.size(), 1u) << sites.dump();
  const double uc = sites[0]["uv"][0], vc = sites[0]["uv"][1];
  EXPECT_GT(std::hypot(uc - 0.5, vc - 0.5), 0.1) << "the coin should be off center: " << sites;
  const int w = 1024, h = 768;
  const Magnification m = magnification(w, h, v);
  int px = -1, py = -1;
  const float at_coin = m.nearest(uc, vc, &px, &py);
  EXPECT_NEAR(at_coin, 2.0, 1e-3) << "pixel (" << px << ", " << py << ") nearest (" << uc << ", "
                                  << vc << ")";
  for (const auto& [x, y] : {std::pair{0, 0}, {w - 1, 0}, {0, h - 1}, {w - 1, h - 1}})
    EXPECT_NEAR(m.at(x, y), 1.0, 1e-6) << "corner pixel (" << x << ", " << y << ")";
}

TEST_F(CameraApi, MagnificationFollowsAnAnimatedCoin) {
  // A coin whose strength is keyframed (as examples/apps/coin_animation.toml does): the map
  // compares the camera with the camera without its coins, whose scene must also lose the coin's
  // keyframes. The coin sits on the sphere's front, on the axis: at the center pixel the zoom is
  // 1 / (1 - m) for the strength m of the frame shown.
  const std::string animated = kScene + R"(
[[camera.coin]]
position = [0.0, 0.0, 1.0]
strength = 0.5
radius = 0.2
affects = "dir"

[[animate]]
key = "camera.coin.0.strength"
keys = [[0, 0.0], [10, 0.5]]
)";
  start(dir.write("animated.toml", animated));
  const int w = 65, h = 49;
  // Frame 0: strength 0, the coin is dropped and every ray is the coin-less camera's.
  Magnification m = magnification(w, h, version());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) ASSERT_EQ(m.at(x, y), 1.0f) << "pixel (" << x << ", " << y << ")";
  for (const auto& [frame, strength] : {std::pair{10.0, 0.5}, {5.0, 0.25}}) {
    const Reply t = post("/api/time", json{{"frame", frame}});
    ASSERT_EQ(t.status, 200) << t.body;
    const int64_t v = body_of(t)["version"];
    const json sites = coins(v)["sites"];
    ASSERT_EQ(sites.size(), 1u) << sites;
    EXPECT_NEAR(sites[0]["strength"].get<double>(), strength, 1e-12) << sites;
    m = magnification(w, h, v);
    EXPECT_NEAR(m.at(w / 2, h / 2), 1 / (1 - strength), 1e-5) << "frame " << frame;
    EXPECT_NEAR(m.at(0, 0), 1.0, 1e-6) << "frame " << frame;
  }
}

TEST_F(CameraApi, MagnificationRejectsBadSizes) {
  for (const std::string q :
       {"width=0&height=10", "width=10&height=0", "width=2000&height=10", "width=10&height=2000",
        "width=1025&height=1", "width=-4&height=4", "width=abc&height=10", "width=10&height=nan",
        "width=&height=", "height=10", "width=10", "", "width=99999999999999&height=3"}) {
    const Reply r = get("/api/magnification?" + q);
    EXPECT_EQ(r.status, 400) << q << ": " << r.body;
    EXPECT_TRUE(body_of(r).contains("error")) << q << ": " << r.body;
  }
  // The bounds themselves are allowed.
  const Reply one = get("/api/magnification?width=1&height=1");
  EXPECT_EQ(one.status, 200) << one.body;
  EXPECT_EQ(one.body.size(), 4u);
}

TEST_F(CameraApi, MagnificationIsNaNExactlyWhereTheCameraHasNoRay) {
  // A 180 degree fisheye whose circle fits the height of a 2:1 image.
  const std::string text = fisheye_scene();
  const fs::path file = dir.write("fisheye.toml", text);
  start(file);
  const Scene scene = load_scene_from_string(text, file, {}, 0);
  const int w = 48, h = 24;
  const Magnification m = magnification(w, h, version());
  int none = 0, some = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      CameraSample cs;
      cs.uv = {(x + 0.5) / w, (y + 0.5) / h};
      const bool ray = scene.camera->generate(cs).has_value();
      const float got = m.at(x, y);
      if (ray) {
        ++some;
        EXPECT_TRUE(std::isfinite(got) && got > 0) << "pixel (" << x << ", " << y << "): " << got;
      } else {
        ++none;
        EXPECT_TRUE(std::isnan(got)) << "pixel (" << x << ", " << y << ") has no ray: " << got;
      }
    }
  EXPECT_GT(none, 0);
  EXPECT_GT(some, 0);
  for (const auto& [x, y] : {std::pair{0, 0}, {w - 1, 0}, {0, h - 1}, {w - 1, h - 1}})
    EXPECT_TRUE(std::isnan(m.at(x, y))) << "corner (" << x << ", " << y << "): " << m.at(x, y);
  EXPECT_TRUE(std::isfinite(m.at(w / 2, h / 2))) << m.at(w / 2, h / 2);
}

// ---- /api/coins ---------------------------------------------------------------------------------

TEST_F(CameraApi, CoinSiteIsWhereTheCoinLessCameraSeesTheCoin) {
  EXPECT_EQ(coins(version())["sites"], json::array());
  const json position = {0.6, 0.0, 0.8};  // on the sphere, facing the camera
  const Reply p = post("/api/project", json{{"position", position}, {"version", version()}});
  ASSERT_EQ(p.status, 200) << p.body;
  const json uvs = body_of(p)["uv"];
  ASSERT_EQ(uvs.size(), 1u) << p.body;

  const int64_t v = edited("camera.coin", json::array({json{
                                              {"position", position},
                                              {"strength", 0.4},
                                              {"radius", 0.2},
                                          }}));
  const json sites = coins(v)["sites"];
  ASSERT_EQ(sites.size(), 1u) << sites.dump();
  const json& s = sites[0];
  EXPECT_EQ(s["coin"], 0) << s;
  EXPECT_NEAR(s["uv"][0].get<double>(), uvs[0][0].get<double>(), 1e-6) << s << " vs " << uvs;
  EXPECT_NEAR(s["uv"][1].get<double>(), uvs[0][1].get<double>(), 1e-6) << s << " vs " << uvs;
  EXPECT_EQ(s["radius"], 0.2) << s;
  EXPECT_EQ(s["strength"], 0.4) << s;
  EXPECT_EQ(s["stiffness"], 1.0) << s;  // the default

  // Strength 0 drops the coin: no site.
  const int64_t v0 = edited("camera.coin.0.strength", 0.0);
  EXPECT_EQ(coins(v0)["sites"], json::array()) << state()["document"]["camera"];
}

TEST_F(CameraApi, CoinsListsEveryCoinInOrder) {
  const int64_t v =
      edited("camera.coin", json::array({json{{"position", {0.0, 0.0, 1.0}}, {"radius", 0.1}},
                                         json{{"position", {0.6, 0.0, 0.8}}, {"strength", -0.3}}}));
  const json sites = coins(v)["sites"];
  ASSERT_EQ(sites.size(), 2u) << sites.dump();
  EXPECT_EQ(sites[0]["coin"], 0);
  EXPECT_EQ(sites[1]["coin"], 1);
  EXPECT_NEAR(sites[0]["uv"][0].get<double>(), 0.5, 1e-9) << sites;  // on the axis
  EXPECT_NEAR(sites[0]["uv"][1].get<double>(), 0.5, 1e-9) << sites;
  EXPECT_EQ(sites[0]["strength"], 0.5) << sites;  // the default
  EXPECT_EQ(sites[0]["radius"], 0.1) << sites;
  EXPECT_EQ(sites[1]["strength"], -0.3) << sites;
  EXPECT_EQ(sites[1]["radius"], 0.25) << sites;  // the default
  EXPECT_EQ(get("/api/coins?version=abc").status, 400);
}

// ---- /api/rays ----------------------------------------------------------------------------------

TEST_F(CameraApi, PerspectiveRaysStartAtTheEyeAndPointThroughTheirCells) {
  const V3 from{3.0, 2.0, 6.0}, at{0.5, 0.0, 0.0};
  const Reply e = post(
      "/api/edit", json{{"version", version()},
                        {"edits", json::array({json{{"key", "camera.look_from"}, {"value", from}},
                                               json{{"key", "camera.look_at"}, {"value", at}}})}});
  ASSERT_EQ(e.status, 200) << e.body;
  const int64_t v = body_of(e)["version"];
  const int nu = 7, nv = 5;
  const json r = rays(fmt::format("nu={}&nv={}&version={}", nu, nv, v));
  ASSERT_EQ(r["nu"], nu);
  ASSERT_EQ(r["nv"], nv);
  ASSERT_EQ(r["org"].size(), size_t(nu * nv));
  ASSERT_EQ(r["dir"].size(), size_t(nu * nv));
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const size_t k = size_t(j) * nu + i;
      ASSERT_TRUE(r["org"][k].is_array() && r["dir"][k].is_array()) << k << ": " << r["org"][k];
      const V3 o = v3(r["org"][k]), d = v3(r["dir"][k]);
      EXPECT_LT(norm(sub(o, from)), 1e-12) << "cell " << i << ", " << j << ": org " << str(o);
      EXPECT_NEAR(norm(d), 1.0, 1e-12) << "cell " << i << ", " << j << ": dir " << str(d);
      const V3 want = perspective_dir(from, at, 50, 64.0 / 48, (i + 0.5) / nu, (j + 0.5) / nv);
      EXPECT_LT(norm(sub(d, want)), 1e-9)
          << "cell " << i << ", " << j << ": dir " << str(d) << ", expected " << str(want);
    }
  // The center cell (odd counts: its center is (0.5, 0.5)) looks at look_at.
  const V3 center = v3(r["dir"][size_t(nv / 2) * nu + nu / 2]);
  EXPECT_LT(angle(center, sub(at, from)), 1e-9) << str(center);
  // The first cell is up and to the left of the axis (v runs down the image).
  const V3 first = v3(r["dir"][0]);
  const V3 f = unit(sub(at, from)), right = unit(cross(f, {0, 1, 0}));
  EXPECT_LT(dot(first, right), 0) << str(first);
  EXPECT_GT(dot(first, cross(right, f)), 0) << str(first);
}

TEST_F(CameraApi, BoxesBoundTheObjectsAndLeaveOutInfinitePlanes) {
  json r = rays("nu=2&nv=2");
  ASSERT_EQ(r["boxes"].size(), 1u) << r["boxes"];  // the sphere; the floor plane has none
  auto expect_box = [](const json& box, const V3& lo, const V3& hi) {
    EXPECT_LT(norm(sub(v3(box[0]), lo)), 1e-9) << box << " vs " << str(lo);
    EXPECT_LT(norm(sub(v3(box[1]), hi)), 1e-9) << box << " vs " << str(hi);
  };
  expect_box(r["boxes"][0], {-1, -1, -1}, {1, 1, 1});

  const V3 c{1.0, 2.0, -3.0};
  const double radius = 0.5;
  const Reply e =
      post("/api/edit",
           json{{"version", version()},
                {"edits", json::array({json{{"key", "object.0.center"}, {"value", c}},
                                       json{{"key", "object.0.radius"}, {"value", radius}}})}});
  ASSERT_EQ(e.status, 200) << e.body;
  r = rays("nu=2&nv=2&version=" + std::to_string(body_of(e)["version"].get<int64_t>()));
  ASSERT_EQ(r["boxes"].size(), 1u) << r["boxes"];
  expect_box(r["boxes"][0], sub(c, {radius, radius, radius}), add(c, {radius, radius, radius}));

  // Without the sphere only the plane is left: no box at all.
  const int64_t v = edited("object.0", nullptr);
  r = rays("nu=2&nv=2&version=" + std::to_string(v));
  EXPECT_EQ(r["boxes"], json::array()) << r["boxes"];
}

TEST_F(CameraApi, RayCountsAreClampedAndNonNumbersAre400) {
  // nu and nv are clamped to [1, 256] (api.cpp); the default is 24 x 14.
  json r = rays("nu=0&nv=3");
  EXPECT_EQ(r["nu"], 1);
  EXPECT_EQ(r["nv"], 3);
  EXPECT_EQ(r["dir"].size(), 3u);
  r = rays("nu=-7&nv=100000");
  EXPECT_EQ(r["nu"], 1);
  EXPECT_EQ(r["nv"], 256);
  EXPECT_EQ(r["dir"].size(), 256u);
  r = rays("");
  EXPECT_EQ(r["nu"], 24);
  EXPECT_EQ(r["nv"], 14);
  EXPECT_EQ(r["org"].size(), 24u * 14u);
  for (const std::string q :
       {"nu=nan", "nv=nan", "nu=inf", "nu=-inf", "nu=abc", "nv=", "nu=1e999"}) {
    const Reply bad = get("/api/rays?" + q);
    EXPECT_EQ(bad.status, 400) << q << ": " << bad.body;
    EXPECT_TRUE(body_of(bad).contains("error")) << q << ": " << bad.body;
  }
}

TEST_F(CameraApi, RaysOfAFisheyeAreNullWhereThereIsNone) {
  start(dir.write("fisheye.toml", fisheye_scene()));
  const int nu = 9, nv = 3;
  const json r = rays(fmt::format("nu={}&nv={}", nu, nv));
  ASSERT_EQ(r["dir"].size(), size_t(nu * nv));
  // The corner cells lie outside the circle; the center cell looks along the axis.
  for (size_t k : {size_t(0), size_t(nu - 1), size_t(nu * nv - nu), size_t(nu * nv - 1)}) {
    EXPECT_TRUE(r["dir"][k].is_null()) << k << ": " << r["dir"][k];
    EXPECT_TRUE(r["org"][k].is_null()) << k << ": " << r["org"][k];
  }
  const V3 center = v3(r["dir"][size_t(nv / 2) * nu + nu / 2]);
  EXPECT_LT(angle(center, {0, 0, -1}), 1e-9) << str(center);
}

TEST_F(CameraApi, ViewsWithoutAVersionWaitForTheFirstState) {
  // Right after the server starts, the preview thread may not have taken up the scene yet; a
  // request naming no version (0) waits for it instead of answering 503 (preview.cpp).
  for (int i = 0; i < 5; ++i) {
    start(dir.write("scene.toml", kScene));
    const Reply r = get("/api/rays?nu=2&nv=2");
    EXPECT_EQ(r.status, 200) << "start " << i << ": " << r.body;
    const Reply c = get("/api/coins");
    EXPECT_EQ(c.status, 200) << "start " << i << ": " << c.body;
    start(dir.write("scene.toml", kScene));
    const Reply m = get("/api/magnification?width=3&height=2");
    EXPECT_EQ(m.status, 200) << "start " << i << ": " << m.body;
    start(dir.write("scene.toml", kScene));
    const Reply p = post("/api/pick", json{{"u", 0.5}, {"v", 0.5}});
    EXPECT_EQ(p.status, 200) << "start " << i << ": " << p.body;
  }
}

// ---- /api/time ----------------------------------------------------------------------------------

// The angle from the view axis of the corner cell's ray (cell 0 of nu x nv) of the perspective
// camera of kScene (aspect 64 : 48) with horizontal field of view `fov`: the image plane at
// distance 1 spans 2 tan(fov / 2) by 2 tan(fov / 2) * 48 / 64.
double corner_angle(double fov, int nu, int nv) {
  const double hw = std::tan(fov * kPi / 360), hh = hw * 48 / 64;
  const double x = (1 - 1.0 / nu) * hw, y = (1 - 1.0 / nv) * hh;
  return std::atan(std::hypot(x, y));
}

TEST_F(CameraApi, TimeMovesAnimatedCameraKeys) {
  const std::string animated = kScene + R"(
[[animate]]
key = "camera.fov"
keys = [[0, 30], [10, 60]]
interpolation = "linear"
)";
  start(dir.write("animated.toml", animated));
  EXPECT_EQ(state()["frame"], 0.0);
  const int nu = 5, nv = 3;
  auto corner = [&](int64_t v) {
    const json r = rays(fmt::format("nu={}&nv={}&version={}", nu, nv, v));
    return angle(v3(r["dir"][0]), {0, 0, -1});
  };
  EXPECT_NEAR(corner(version()), corner_angle(30, nu, nv), 1e-9);

  Reply frame = get("/api/frame?after=0");
  ASSERT_EQ(frame.status, 200);
  uint64_t seq = std::stoull(frame.header("x-frame-seq"));
  const int64_t v0 = version();

  for (const auto& [f, fov] : {std::pair{5.0, 45.0}, {10.0, 60.0}, {20.0, 60.0}, {2.5, 37.5}}) {
    const Reply t = post("/api/time", json{{"frame", f}});
    ASSERT_EQ(t.status, 200) << t.body;
    const int64_t v = body_of(t)["version"];
    EXPECT_GT(v, v0) << "frame " << f;
    EXPECT_EQ(body_of(t)["state"]["frame"], f) << t.body.substr(0, 300);
    EXPECT_EQ(state()["frame"], f);
    EXPECT_EQ(state()["version"], v);
    EXPECT_NEAR(corner(v), corner_angle(fov, nu, nv), 1e-9) << "frame " << f << ", fov " << fov;
  }
  // The document itself is unchanged: the animation is applied to the scene it loads.
  EXPECT_EQ(state()["document"]["camera"]["fov"], 50);

  // The preview shows the newest version.
  const int64_t v = version();
  int64_t shown = -1;
  for (int i = 0; i < 200 && shown != v; ++i) {
    frame = get("/api/frame?timeout=5&after=" + std::to_string(seq));
    if (frame.status != 200) break;
    seq = std::stoull(frame.header("x-frame-seq"));
    shown = std::stoll(frame.header("x-frame-version"));
  }
  EXPECT_EQ(shown, v);
}

TEST_F(CameraApi, TimeWithoutANumberIs400) {
  const int64_t v = version();
  for (const json& body :
       {json{{"frame", "5"}}, json::object(), json{{"frame", nullptr}}, json{{"frame", 2e9}},
        json{{"frame", json::array({1})}}, json{{"frame", true}}}) {
    const Reply r = post("/api/time", body);
    EXPECT_EQ(r.status, 400) << body.dump() << ": " << r.body;
    EXPECT_TRUE(body_of(r).contains("error")) << r.body;
  }
  EXPECT_EQ(post("/api/time", std::string("{\"frame\": ")).status, 400);  // malformed JSON
  EXPECT_EQ(post("/api/time", std::string("[5]")).status, 400);
  EXPECT_EQ(version(), v);
  EXPECT_EQ(state()["frame"], 0.0);
}

}  // namespace
}  // namespace anamorph::test
