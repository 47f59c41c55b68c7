// Ray-table cameras from `anamorph rays` output: the round trip rays -> table -> rays, and a
// render through the table against the camera it was sampled from.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "cli_util.h"
#include "io/image_io.h"
#include "scene/scene_loader.h"
#include "test_util.h"

namespace anamorph {
namespace {

namespace fs = std::filesystem;

fs::path temp_dir(const std::string& name) {
  const fs::path d =
      fs::temp_directory_path() / ("anamorph_table_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

const fs::path kFisheye = test::source_dir() / "examples/apps/fisheye_180.toml";

// The fisheye scene with its camera replaced by org = table and dir = table from `exr`.
std::string table_scene(const fs::path& dir, const fs::path& exr) {
  const fs::path p = dir / "table.toml";
  std::ofstream(p) << "include = \""
                   << (test::source_dir() / "examples/apps/plaza_world.toml").string()
                   << "\"\n[render]\nintegrator = \"whitted\"\nmax_depth = 5\n"
                   << "[camera.org]\ntype = \"table\"\nfile = \"" << exr.string() << "\"\n"
                   << "[camera.dir]\ntype = \"table\"\nfile = \"" << exr.string() << "\"\n";
  return p.string();
}

TEST(TableCamera, RaysOfAFisheyeRoundTripToTheSamePixelCenters) {
  const fs::path d = temp_dir("roundtrip");
  const int n = 257;
  const auto r = test::run_cli("rays " + kFisheye.string() + " --width 257 --height 257 -o " +
                               (d / "rays.exr").string());
  ASSERT_EQ(r.code, 0) << r.out;
  const Scene original = load_scene(kFisheye), table = load_scene(table_scene(d, d / "rays.exr"));
  int rays = 0;
  double worst = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const CameraSample s{{(i + 0.5) / n, (j + 0.5) / n}};
      const auto a = original.camera->generate(s), b = table.camera->generate(s);
      ASSERT_EQ(bool(a), bool(b)) << "pixel " << i << ", " << j;
      if (!a) continue;
      ++rays;
      worst = std::max({worst, length(a->org - b->org), length(a->dir - b->dir)});
    }
  EXPECT_LT(worst, 1e-12) << "largest difference of origin or direction over " << rays << " rays";
  EXPECT_GT(rays, 50000);
  fs::remove_all(d);
}

TEST(TableCamera, RenderAgreesWithTheSampledCameraObjectByObject) {
  // A 512 x 512 table rendered at 384 x 384: no render pixel center is a table sample, so the
  // Catmull-Rom interpolation and the no-ray boundary between samples are what is compared.
  const fs::path d = temp_dir("render");
  auto r = test::run_cli("rays " + kFisheye.string() + " --width 512 --height 512 -o " +
                         (d / "rays.exr").string());
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string common =
      " --width 384 --height 384 --spp 1 --sampler center --set render.antialias=uniform "
      "--aov id -o ";
  r = test::run_cli("render " + kFisheye.string() + common + (d / "a.exr").string());
  ASSERT_EQ(r.code, 0) << r.out;
  r = test::run_cli("render " + table_scene(d, d / "rays.exr") + common + (d / "b.exr").string());
  ASSERT_EQ(r.code, 0) << r.out;
  int w, h, w2, h2;
  const auto a = read_exr_channels(d / "a.exr", &w, &h),
             b = read_exr_channels(d / "b.exr", &w2, &h2);
  ASSERT_EQ(w, w2);
  const auto& ia = a.at("id.id");
  const auto& ib = b.at("id.id");
  size_t same = 0;
  for (size_t k = 0; k < ia.size(); ++k) same += ia[k] == ib[k];
  const double fraction = double(same) / double(ia.size());
  EXPECT_GE(fraction, 0.999) << ia.size() - same << " of " << ia.size()
                             << " pixels see another object (or no ray) through the table";
  fs::remove_all(d);
}

}  // namespace
}  // namespace anamorph
