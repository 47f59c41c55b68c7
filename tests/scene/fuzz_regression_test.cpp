// Every input a fuzz target found (tests/data/fuzz/TARGET/), run the way its target runs it, in
// the normal suite (and so under ASan + UBSan in scripts/test): a clean load or a clean error,
// finite rays with unit directions, packets equal to single rays.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "scene/loaders.h"
#include "scene/scene_loader.h"
#include "scene/toml_reader.h"
#include "test_util.h"

namespace anamorph {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> findings(const std::string& target) {
  std::vector<fs::path> out;
  const fs::path dir = test::data_dir() / "fuzz" / target;
  if (fs::exists(dir))
    for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path());
  return out;
}

TEST(FuzzFindings, CameraTablesGiveFiniteRaysAndPacketsEqualSingleRays) {
  const auto files = findings("camera");
  ASSERT_FALSE(files.empty());
  for (const fs::path& f : files) {
    Scene scene;
    try {
      scene = load_scene_from_string(
          "[image]\nwidth = 16\nheight = 12\n[camera]\n" + test::read_text(f), f.filename());
    } catch (const SceneError&) {
      continue;  // a clean rejection
    }
    CameraSample samples[kCameraBatch];
    for (int i = 0; i < kCameraBatch; ++i) samples[i].uv = {(i % 4 + 0.5) / 4, (i / 4 + 0.5) / 4};
    CameraRayBatch batch;
    scene.camera->generate_batch(samples, kCameraBatch, &batch);
    for (int i = 0; i < kCameraBatch; ++i) {
      const auto r = scene.camera->generate(samples[i]);
      ASSERT_EQ(bool(r), batch.valid[i]) << f << " lane " << i;
      if (!r) continue;
      EXPECT_TRUE(is_finite(r->org) && is_finite(r->dir)) << f << " lane " << i;
      EXPECT_NEAR(length(r->dir), 1, 1e-9) << f << " lane " << i;
      const CameraRay b = batch.ray(i);
      EXPECT_EQ(std::memcmp(&b, &*r, sizeof b), 0) << f << " lane " << i;
    }
  }
}

TEST(FuzzFindings, ModelsLoadOrFailCleanly) {
  int n = 0;
  for (const char* target : {"ply", "obj", "gltf", "glb", "stl"})
    for (const fs::path& f : findings(target)) {
      ++n;
      try {
        const LoadedModel m = load_model(f);
        EXPECT_GE(m.triangle_count(), 0u);
      } catch (const LoadError& e) {
        EXPECT_NE(std::string(e.what()).find(f.string()), std::string::npos) << e.what();
      }
    }
  EXPECT_GT(n, 0);
}

}  // namespace
}  // namespace anamorph
