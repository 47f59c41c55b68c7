// FrameOutput: tiles in any order become files written strip by strip; an unfinished frame
// (interrupted, or stopped by a time limit) is written with its missing tiles empty. Rows of
// tiles none of which arrived take a shortcut (one encoded strip appended again and again); the
// files must read back exactly as if each missing tile had been resolved on its own.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "io/image_io.h"
#include "render/frame_output.h"

namespace anamorph {
namespace {

namespace fs = std::filesystem;

// 70 x 100 in 32-pixel tiles: 3 columns (the last 6 wide), 4 rows (the last 4 high).
FrameOutputSpec spec(const fs::path& dir) {
  FrameOutputSpec s;
  s.width = 70, s.height = 100, s.tile_size = 32;
  s.aovs = {Aov::Albedo, Aov::Depth};
  s.files = {dir / "out.png", dir / "out.exr"};
  return s;
}

// A tile whose pixels all saw one sample of a colour unique to the tile.
ResolvedTile rendered(const FrameOutput& out, size_t index) {
  const TileRect r = out.grid().rect(index);
  TileBuffer t(r, out.spec().aovs);
  AovSample a;
  a.hit = true, a.albedo = {0.5, 0.25, 0.125}, a.depth = double(index + 1);
  const Color c{0.1 * double(index + 1), 0.5, 0.25};
  for (int y = r.y0; y < r.y1; ++y)
    for (int x = r.x0; x < r.x1; ++x) t.add(x, y, c, 1.0, a);
  return resolve(index, t, out.plan());
}

// The plane of `t` holding `layer` as floats.
const std::vector<float>& floats(const FrameOutput& out, const ResolvedTile& t,
                                 const std::string& layer) {
  const auto& plan = out.plan();
  const auto at = std::find(plan.begin(), plan.end(), LayerRequest{layer, Encoding::Float32});
  return t.planes.at(size_t(at - plan.begin())).f32;
}

struct Expected {
  std::vector<float> rgba, albedo, depth;  // per pixel, as resolve() gives them
};

// Every pixel as resolve() gives it for its tile: rendered or empty.
Expected expected(const FrameOutput& out, const std::vector<size_t>& added) {
  const auto& g = out.grid();
  Expected e;
  e.rgba.resize(size_t(g.width) * size_t(g.height) * 4);
  e.albedo.resize(size_t(g.width) * size_t(g.height) * 3);
  e.depth.resize(size_t(g.width) * size_t(g.height));
  for (size_t i = 0; i < g.count(); ++i) {
    const TileRect r = g.rect(i);
    const bool done = std::find(added.begin(), added.end(), i) != added.end();
    const ResolvedTile t =
        done ? rendered(out, i) : resolve(i, TileBuffer(r, out.spec().aovs), out.plan());
    const std::vector<float>&rgba = floats(out, t, ""), &albedo = floats(out, t, "albedo"),
          &depth = floats(out, t, "depth");
    size_t k = 0;
    for (int y = r.y0; y < r.y1; ++y)
      for (int x = r.x0; x < r.x1; ++x, ++k) {
        const size_t p = size_t(y) * size_t(g.width) + size_t(x);
        std::copy_n(&rgba[k * 4], 4, &e.rgba[p * 4]);
        std::copy_n(&albedo[k * 3], 3, &e.albedo[p * 3]);
        e.depth[p] = depth[k];
      }
  }
  return e;
}

void expect_files(const fs::path& png, const fs::path& exr, const Expected& e) {
  const Image img = read_image(png, false);
  ASSERT_EQ(img.width, 70);
  ASSERT_EQ(img.height, 100);
  int width = 0, height = 0;
  auto ch = read_exr_channels(exr, &width, &height);
  ASSERT_EQ(width, 70);
  ASSERT_EQ(height, 100);
  const char* rgba[] = {"R", "G", "B", "A"};
  const char* albedo[] = {"albedo.R", "albedo.G", "albedo.B"};
  for (size_t p = 0; p < e.depth.size(); ++p) {
    const int x = int(p % 70), y = int(p / 70);
    unsigned char bytes[4];
    encode_rgba8(&e.rgba[p * 4], bytes);
    for (int c = 0; c < 4; ++c) {
      const float v = e.rgba[p * 4 + size_t(c)];
      ASSERT_NEAR(img.pixels[p * 4 + size_t(c)], float(bytes[c]) / 255, 1e-6) << x << "," << y;
      ASSERT_EQ(ch.at(rgba[c])[p], v) << rgba[c] << " at " << x << "," << y;
    }
    for (int c = 0; c < 3; ++c)
      ASSERT_EQ(ch.at(albedo[c])[p], e.albedo[p * 3 + size_t(c)]) << x << "," << y;
    const float d = e.depth[p], got = ch.at("depth.Z")[p];
    ASSERT_TRUE(d == got || (std::isnan(d) && std::isnan(got))) << d << " vs " << got;
  }
}

class FrameOutputTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(::testing::TempDir()) /
           ("frame_output_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(FrameOutputTest, TheImageSoFarHasItsMissingTilesEmptyWhateverRowsArrived) {
  FrameOutput out(spec(dir_));
  ASSERT_EQ(out.grid().cols, 3);
  ASSERT_EQ(out.grid().rows, 4);
  // Row 0 and the short last row: nothing (the shortcut, at two heights); row 1 whole; row 2 one
  // tile, added out of order.
  const std::vector<size_t> added{7, 3, 4, 5};
  for (size_t i : added) out.add(rendered(out, i));
  out.commit_partial(".partial");
  EXPECT_FALSE(fs::exists(dir_ / "out.png"));
  expect_files(dir_ / "out.partial.png", dir_ / "out.partial.exr", expected(out, added));
}

TEST_F(FrameOutputTest, AnIncompleteFrameWithNoTileIsAllEmpty) {
  FrameOutput out(spec(dir_));
  out.commit_incomplete();
  expect_files(dir_ / "out.png", dir_ / "out.exr", expected(out, {}));
}

TEST_F(FrameOutputTest, ACompleteFrameInAnyOrderIsEveryTile) {
  FrameOutput out(spec(dir_));
  std::vector<size_t> added;
  for (size_t i = out.grid().count(); i-- > 0;) added.push_back(i);
  for (size_t i : added) out.add(rendered(out, i));
  out.commit();
  expect_files(dir_ / "out.png", dir_ / "out.exr", expected(out, added));
}

// Pixel (x, y)'s samples in the test below: 0 to 3 of them, some with no ray, colours negative,
// zero (both signs), in [0, 1], above 1 and huge, so that every branch of the resolve and of the
// sRGB encoding is met.
void add_samples(TileBuffer& t, const TileRect& r) {
  const double colours[] = {0.5, -0.25, -0.0, 0.0, 1.5, 3e38, 1e-5, 0.0031, 0.999};
  for (int y = r.y0; y < r.y1; ++y)
    for (int x = r.x0; x < r.x1; ++x) {
      const int k = x * 7 + y * 13, samples = k % 4;
      for (int s = 0; s < samples; ++s) {
        const double c = colours[size_t(k + s) % 9];
        const Color L{c, colours[size_t(k + 2 * s) % 9], 0.125 * s};
        const double alpha = (k + s) % 5 == 0 ? 0.0 : 1.0;  // some samples without a ray
        t.add(x, y, L, alpha, AovSample{});
      }
    }
}

TEST(ResolveRgba8, WritesTheBytesOfResolveIntoTheFrameAndNothingElse) {
  const TileRect r{70, 3, 150, 8};  // 80 wide: more than one 64-pixel chunk
  TileBuffer t(r, {});
  add_samples(t, r);
  const ResolvedTile planes = resolve(0, t, {{"", Encoding::Srgb8}});
  const size_t W = 200, stride = W * 4;
  std::vector<unsigned char> frame(stride * 12, 7);
  resolve_rgba8(t, &frame[(size_t(r.y0) * W + size_t(r.x0)) * 4], stride);
  for (size_t y = 0; y < 12; ++y)
    for (size_t x = 0; x < W; ++x)
      for (size_t c = 0; c < 4; ++c) {
        const bool inside = int(x) >= r.x0 && int(x) < r.x1 && int(y) >= r.y0 && int(y) < r.y1;
        const unsigned char want =
            inside ? planes.planes[0].u8[((y - size_t(r.y0)) * 80 + x - size_t(r.x0)) * 4 + c] : 7;
        ASSERT_EQ(int(frame[y * stride + x * 4 + c]), int(want))
            << "(" << x << ", " << y << ") channel " << c;
      }
}

}  // namespace
}  // namespace anamorph
