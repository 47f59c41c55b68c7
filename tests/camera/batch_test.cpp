// Batched ray generation (the renderer's packets) gives exactly the rays of generate(), for every
// preset, a free-form camera with dependent directions, and coins.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "camera/presets.h"
#include "camera/virtual_camera.h"
#include "math/rng.h"
#include "preset_test_util.h"
#include "scene/scene_loader.h"

namespace anamorph {

namespace {

// Random samples, a few exact corners and edges, batches of odd sizes (partial packets).
void expect_batch_equals_single(const Camera& cam, const std::string& label) {
  Rng rng(5, 6);
  constexpr int kN = 53;
  CameraSample s[kN];
  for (auto& x : s) x.uv = {rng.uniform(), rng.uniform()}, x.lens = {rng.uniform(), rng.uniform()};
  s[0].uv = {0, 0}, s[1].uv = {1, 1}, s[2].uv = {0.5, 0.5}, s[3].uv = {1, 0};
  CameraRay out[kN];
  bool valid[kN];
  int n_valid = 0;
  // Full packets, single samples and partial packets (sizes sum to kN).
  int base = 0;
  for (int n : {16, 1, 16, 7, 13}) {
    CameraRayBatch b;
    cam.generate_batch(s + base, n, &b);
    for (int k = 0; k < n; ++k) out[base + k] = b.ray(k), valid[base + k] = b.valid[k];
    base += n;
  }
  ASSERT_EQ(base, kN);
  for (int i = 0; i < kN; ++i) {
    const auto r = cam.generate(s[i]);
    ASSERT_EQ(valid[i], bool(r)) << label << " sample " << i << " at " << test::str(s[i].uv);
    if (!r) continue;
    ++n_valid;
    EXPECT_EQ(0, std::memcmp(&out[i], &*r, sizeof(CameraRay)))
        << label << " sample " << i << " at " << test::str(s[i].uv) << ": batch org "
        << test::str(out[i].org) << " dir " << test::str(out[i].dir) << " vs single org "
        << test::str(r->org) << " dir " << test::str(r->dir);
  }
  EXPECT_GT(n_valid, 0) << label << ": no sample had a ray";
}

class EveryPresetBatch : public ::testing::TestWithParam<test::PresetCase> {};

}  // namespace

TEST_P(EveryPresetBatch, SameBitsAsOneByOne) {
  const auto& c = GetParam();
  expect_batch_equals_single(test::camera(c.preset, c.toml, c.img), c.label());
}

INSTANTIATE_TEST_SUITE_P(Presets, EveryPresetBatch, ::testing::ValuesIn(test::preset_cases()),
                         [](const auto& param_info) {
                           return std::to_string(param_info.index) + "_" + param_info.param.preset;
                         });

TEST(CameraBatch, FreeFormNormalAndCoinsSameBitsAsOneByOne) {
  const char* spline =
      "[camera]\n"
      "org = { type = \"bspline\", points = ["
      "[[-2, 2.4, 0.6], [-1, 2.4, 0.4], [0, 2.4, 0.3], [1, 2.4, 0.4], [2, 2.4, 0.6]],"
      "[[-2, 1.2, 0.3], [-1, 1.2, 0.1], [0, 1.2, 0], [1, 1.2, 0.1], [2, 1.2, 0.3]],"
      "[[-2, 0, 0], [-1, 0, -0.1], [0, 0, -0.2], [1, 0, -0.1], [2, 0, 0]],"
      "[[-2, -1.2, 0.3], [-1, -1.2, 0.1], [0, -1.2, 0], [1, -1.2, 0.1], [2, -1.2, 0.3]],"
      "[[-2, -2.4, 0.6], [-1, -2.4, 0.4], [0, -2.4, 0.3], [1, -2.4, 0.4], [2, -2.4, 0.6]]] }\n"
      "dir = { type = \"normal\" }\n"
      "transform = { translate = [1, 2, 3], rotate = [30, 0, 1, 0] }\n";
  const Scene plain = load_scene_from_string(spline, "spline.toml");
  expect_batch_equals_single(*plain.camera, "bspline + normal");
  const std::string coins =
      std::string(spline) +
      "[[camera.coin]]\nposition = [1, 2, -1]\nradius = 0.3\nstrength = 0.6\n";
  const Scene with_coins = load_scene_from_string(coins, "spline_coin.toml");
  expect_batch_equals_single(*with_coins.camera, "bspline + normal + coin");
  const Scene fisheye_coin = load_scene_from_string(
      "[camera]\npreset = \"fisheye\"\nfov = 200\n[[camera.coin]]\nposition = [0.3, 0.2, -2]\n"
      "radius = 0.2\nstrength = 0.8\n",
      "fisheye_coin.toml");
  expect_batch_equals_single(*fisheye_coin.camera, "fisheye + coin");
}

// Direction functions that claim unit length (the finish then skips normalizing) must return
// unit vectors with perpendicular derivatives; and a rig that scales must still get unit rays.
TEST(CameraBatch, UnitLengthClaimsHoldAndScaledRigsStillNormalize) {
  const std::pair<const char*, const char*> claims[] = {
      {"fisheye", "fov = 220"},
      {"mirror_ball", ""},
      {"equirectangular", ""},
      {"lambert_equal_area", ""},
      {"ods", "pole_merge = [60, 80]"},
      {"opencv_fisheye", "fx = 300\nfy = 300\nk1 = 0.05"},
      {"cylindrical", "projection = \"orthographic\""}};
  // The presets above, and the dependent normal direction on a sphere of radius 2.
  std::vector<std::pair<std::string, VirtualCameraParts>> cases;
  for (const auto& [name, toml] : claims)
    cases.emplace_back(name, make_preset(name, toml, {640, 480}));
  VirtualCameraParts normal;
  normal.org = make_org("sphere", "radius = 2");
  normal.dir = make_dir("normal");
  cases.emplace_back("sphere + normal", std::move(normal));
  Rng rng(9, 10);
  for (auto& [name, parts] : cases) {
    ASSERT_TRUE(parts.dir->unit_length()) << name;
    int checked = 0;
    for (int k = 0; k < 400; ++k) {
      const Vec2 uv{rng.uniform(), rng.uniform()};
      SurfaceSample o;
      DirSample d;
      if (!parts.org->eval(uv, &o) || !parts.dir->eval(uv, o, &d)) continue;
      ++checked;
      EXPECT_NEAR(length(d.d), 1, 4e-16) << name << " at " << test::str(uv);
      const double scale = 1 + length(d.dd_du) + length(d.dd_dv);
      EXPECT_LT(std::abs(dot(d.d, d.dd_du)) + std::abs(dot(d.d, d.dd_dv)), 1e-13 * scale)
          << name << " at " << test::str(uv) << " d " << test::str(d.d) << " dd_du "
          << test::str(d.dd_du) << " dd_dv " << test::str(d.dd_dv);
    }
    EXPECT_GT(checked, 100) << name;
    // The same function under a rig that scales by 3: the finish must normalize again.
    parts.world_from_camera = Transform::scale({3, 3, 3}) * parts.world_from_camera;
    const VirtualCamera cam(std::move(parts));
    CameraSample s[16];
    for (auto& x : s) x.uv = {rng.uniform(), rng.uniform()};
    CameraRayBatch b;
    cam.generate_batch(s, 16, &b);
    for (int i = 0; i < 16; ++i) {
      if (!b.valid[i]) continue;
      EXPECT_NEAR(length(b.direction(i)), 1, 1e-15)
          << name << " scaled rig at " << test::str(s[i].uv);
    }
  }
  // And a direction function that is not unit (the cylinder) does not claim it.
  EXPECT_FALSE(make_preset("cylindrical", "", {640, 480}).dir->unit_length());
  EXPECT_FALSE(make_preset("dome", "eye_offset = [0, 0.2, 0]", {640, 480}).dir->unit_length());
}

// Directions that say they read only p, dpdu, dpdv of their origins get the first-order origin
// batch: its fields are eval_batch's bit for bit, and the directions are the same bits when every
// other field of the origin batch is NaN.
TEST(CameraBatch, FirstOrderOriginsAreEnoughForDirectionsThatSaySo) {
  int claiming = 0;
  for (const auto& c : test::preset_cases()) {
    const VirtualCameraParts parts = make_preset(c.preset, c.toml, c.img);
    if (parts.dir->reads_org_beyond_first_order()) continue;
    ++claiming;
    Rng rng(11, 12);
    double u[16], v[16];
    for (int i = 0; i < 16; ++i) u[i] = rng.uniform(), v[i] = rng.uniform();
    u[0] = 0, v[0] = 0, u[1] = 1, v[1] = 1;
    SurfaceBatch full, first;
    parts.org->eval_batch(u, v, 16, &full);
    for (auto* a : {&first.n, &first.dndu, &first.dndv, &first.dpduu, &first.dpduv, &first.dpdvv})
      for (auto& row : *a) std::fill(std::begin(row), std::end(row), std::nan(""));
    parts.org->eval_batch_first_order(u, v, 16, &first);
    DirBatch d_full, d_first;
    parts.dir->eval_batch(u, v, 16, full, &d_full);
    parts.dir->eval_batch(u, v, 16, first, &d_first);
    for (int i = 0; i < 16; ++i) {
      const std::string at = c.label() + " at " + test::str(Vec2{u[i], v[i]});
      ASSERT_EQ(full.ok[i], first.ok[i]) << at;
      ASSERT_EQ(d_full.ok[i], d_first.ok[i]) << at;
      for (const auto& [a, b] : {std::pair{&full.p, &first.p}, std::pair{&full.dpdu, &first.dpdu},
                                 std::pair{&full.dpdv, &first.dpdv}})
        EXPECT_TRUE(SurfaceBatch::at(*a, i) == SurfaceBatch::at(*b, i))
            << at << ": " << test::str(SurfaceBatch::at(*a, i)) << " vs "
            << test::str(SurfaceBatch::at(*b, i));
      if (!d_full.ok[i]) continue;
      const DirSample x = d_full.lane(i), y = d_first.lane(i);
      EXPECT_EQ(0, std::memcmp(&x, &y, sizeof x))
          << at << ": direction " << test::str(x.d) << " vs " << test::str(y.d);
    }
  }
  EXPECT_GE(claiming, 3) << "light_field, integral and ods claim it";
  // Dependent directions read the normal and second derivatives.
  EXPECT_TRUE(make_dir("normal")->reads_org_beyond_first_order());
  EXPECT_TRUE(make_dir("tangent_u")->reads_org_beyond_first_order());
}

}  // namespace anamorph
