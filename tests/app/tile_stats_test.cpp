// `render --stats FILE`: every tile's cost as JSON. The file must account for the whole render:
// each tile once per pass, rectangles covering the image, samples and rays adding up to the
// render's totals.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "app/cli_util.h"
#include "test_util.h"

namespace anamorph {
namespace {

namespace fs = std::filesystem;

struct Scratch {
  fs::path dir = fs::temp_directory_path() / ("anamorph_stats_" + std::to_string(getpid()));
  Scratch() { fs::create_directories(dir); }
  ~Scratch() { fs::remove_all(dir); }
};

std::string demo_scene() { return (test::source_dir() / "examples/apps/domemaster.toml").string(); }

nlohmann::json render_with_stats(const Scratch& s, const std::string& settings) {
  const fs::path stats = s.dir / "stats.json";
  const test::CliResult r =
      test::run_cli("render " + demo_scene() + " --threads 2 " + settings + " -o " +
                    (s.dir / "out.png").string() + " --stats " + stats.string());
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("tile costs written to " + stats.string()), std::string::npos) << r.out;
  return nlohmann::json::parse(test::read_text(stats));
}

TEST(TileStats, UniformTilesCoverTheImageOnceAndAddUp) {
  Scratch s;
  const nlohmann::json j = render_with_stats(
      s, "--width 72 --height 40 --integrator path --spp 3 --set render.tile_size=16");
  ASSERT_EQ(j["width"], 72);
  ASSERT_EQ(j["tile_size"], 16);
  const auto& tiles = j["tiles"];
  ASSERT_EQ(tiles.size(), j["tiles_total"].get<size_t>());
  ASSERT_EQ(tiles.size(), 5u * 3u);  // ceil(72/16) x ceil(40/16)
  std::set<size_t> seen;
  uint64_t pixels = 0, samples = 0, rays = 0;
  for (const auto& t : tiles) {
    EXPECT_TRUE(seen.insert(t["index"].get<size_t>()).second) << t.dump();
    EXPECT_EQ(t["pass"], 0);
    EXPECT_GE(t["seconds"].get<double>(), 0.0);
    EXPECT_LE(t["start"].get<double>() + t["seconds"].get<double>(),
              j["seconds"].get<double>() + 1e-3)
        << t.dump();
    pixels += t["w"].get<uint64_t>() * t["h"].get<uint64_t>();
    samples += t["samples"].get<uint64_t>();
    rays += t["rays"].get<uint64_t>();
  }
  EXPECT_EQ(pixels, 72u * 40u);
  EXPECT_EQ(samples, 72u * 40u * 3u);
  EXPECT_EQ(samples, j["samples"].get<uint64_t>());
  EXPECT_EQ(rays, j["rays"].get<uint64_t>());
}

// Per-pixel adaptive sampling: a tile appears once per pass it took part in, and later passes
// take fewer samples.
TEST(TileStats, AdaptivePassesAreListedPerTile) {
  Scratch s;
  const nlohmann::json j = render_with_stats(
      s,
      "--width 64 --height 64 --integrator path --set render.antialias=\\\"pixel\\\" --set "
      "render.max_spp=64 --set render.tile_size=16");
  std::set<std::pair<int, size_t>> seen;
  uint64_t samples = 0;
  int last_pass = 0;
  for (const auto& t : j["tiles"]) {
    const int pass = t["pass"].get<int>();
    EXPECT_GE(pass, last_pass) << "sorted by pass";
    last_pass = pass;
    EXPECT_TRUE(seen.insert({pass, t["index"].get<size_t>()}).second) << t.dump();
    samples += t["samples"].get<uint64_t>();
  }
  EXPECT_GT(last_pass, 0);
  EXPECT_EQ(samples, j["samples"].get<uint64_t>());
}

TEST(TileStats, FramesNeedAPattern) {
  Scratch s;
  const std::string scene = (s.dir / "anim.toml").string();
  std::ofstream(scene) << "[image]\nwidth = 16\nheight = 16\n[[object]]\ntype = \"sphere\"\n"
                          "[[animate]]\nkey = \"camera.fov\"\nkeys = [[0, 30], [1, 60]]\n";
  const std::string out = (s.dir / "f_%d.png").string();
  const test::CliResult bad = test::run_cli("render " + scene + " --frames 0:1 -o " + out +
                                            " --stats " + (s.dir / "s.json").string());
  EXPECT_EQ(bad.code, 2) << bad.out;
  EXPECT_NE(bad.out.find("needs a frame-number pattern"), std::string::npos) << bad.out;
  const test::CliResult ok = test::run_cli("render " + scene + " -q --frames 0:1 -o " + out +
                                           " --stats " + (s.dir / "s_%d.json").string());
  ASSERT_EQ(ok.code, 0) << ok.out;
  for (int f = 0; f < 2; ++f) {
    const auto j =
        nlohmann::json::parse(test::read_text(s.dir / ("s_" + std::to_string(f) + ".json")));
    EXPECT_EQ(j["frame"].get<double>(), f);
  }
}

}  // namespace
}  // namespace anamorph
