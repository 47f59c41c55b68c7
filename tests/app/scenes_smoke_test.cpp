// Every bundled scene of the paper's Table 1 (examples/paper) and of the applications
// (examples/apps) still loads and renders: at 96 pixels wide with 2 samples per pixel, through the
// library (load_scene, Renderer, Film), without errors, warnings or NaN samples, and into an image
// that is not uniform. Animated scenes render their last keyframe, where the animation has done
// the most. Files named *world.toml hold only objects for the scenes to include; they are not
// scenes themselves.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

#include "camera/presets.h"
#include "render/renderer.h"
#include "scene/scene_loader.h"
#include "test_util.h"

namespace anamorph {
namespace {

namespace fs = std::filesystem;

constexpr int kWidth = 96;
constexpr int kSpp = 2;

struct SceneFile {
  std::string group;  // "paper" or "apps"
  fs::path path;
};

// gtest prints the parameter of a failing test with this.
void PrintTo(const SceneFile& f, std::ostream* os) { *os << f.path.string(); }

bool is_object_file(const fs::path& p) {
  const std::string name = p.filename().string();
  return name.size() >= 10 && name.compare(name.size() - 10, 10, "world.toml") == 0;
}

std::vector<SceneFile> scene_files() {
  std::vector<SceneFile> out;
  for (const char* group : {"paper", "apps"}) {
    const fs::path dir = test::source_dir() / "examples" / group;
    if (!fs::is_directory(dir)) continue;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir))
      if (e.is_regular_file() && e.path().extension() == ".toml" && !is_object_file(e.path()))
        files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const fs::path& f : files) out.push_back({group, f});
  }
  return out;
}

std::string test_name(const testing::TestParamInfo<SceneFile>& info) {
  std::string name = info.param.group + "_" + info.param.path.stem().string();
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const std::string& x : v) s += "\n  " + x;
  return s;
}

class SceneSmoke : public testing::TestWithParam<SceneFile> {};

TEST_P(SceneSmoke, RendersSmallWithoutNaNAndNotUniform) {
  const fs::path& file = GetParam().path;
  // The file's own size gives the aspect of the small render.
  const Scene full = load_scene(file);
  const int height =
      std::max(1, int(std::lround(double(kWidth) * full.render.height / full.render.width)));
  const std::vector<std::string> overrides = {"image.width=" + std::to_string(kWidth),
                                              "image.height=" + std::to_string(height),
                                              "render.spp=" + std::to_string(kSpp)};
  const double frame = full.animated.empty() ? 0.0 : full.last_key;
  const Scene scene = load_scene(file, overrides, frame);
  EXPECT_TRUE(scene.warnings.empty()) << file << " warns:" << join(scene.warnings);
  ASSERT_EQ(scene.render.width, kWidth);
  ASSERT_EQ(scene.render.height, height);

  const Renderer renderer(scene);
  Film film(kWidth, height, {});
  RenderOptions opt;
  const RenderStats stats = renderer.render(film, opt);
  EXPECT_EQ(stats.nan_samples, 0u) << file << ": first non-finite sample at pixel (" << stats.nan_x
                                   << ", " << stats.nan_y << "), sample " << stats.nan_sample;
  EXPECT_FALSE(stats.cancelled);

  double lo = INFINITY, hi = -INFINITY, covered = 0;
  int non_finite = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const Color c = film.pixel(x, y);
      if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z)) {
        ++non_finite;
        continue;
      }
      const double l = 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
      lo = std::min(lo, l);
      hi = std::max(hi, l);
      covered += film.alpha(x, y);
    }
  EXPECT_EQ(non_finite, 0) << file;
  EXPECT_GT(covered, 0.5 * kWidth * height) << file << ": most pixels have no ray (total coverage "
                                            << covered << " of " << kWidth * height << ")";
  EXPECT_GT(hi - lo, 0.1) << file << ": the image is uniform (luminance from " << lo << " to " << hi
                          << ")";
}

INSTANTIATE_TEST_SUITE_P(Examples, SceneSmoke, testing::ValuesIn(scene_files()), test_name);

// Table 1 has fourteen images: examples/paper/01.toml ... 14.toml, each at the table's size.
TEST(SceneFiles, PaperHasTheFourteenRowsOfTableOne) {
  for (int i = 1; i <= 14; ++i) {
    char name[16];
    std::snprintf(name, sizeof name, "%02d.toml", i);
    const fs::path file = test::source_dir() / "examples" / "paper" / name;
    ASSERT_TRUE(fs::exists(file)) << file;
    const Scene s = load_scene(file);
    const bool wide = i == 3 || i == 4;
    EXPECT_EQ(s.render.width, wide ? 1280 : 640) << file;
    EXPECT_EQ(s.render.height, wide ? 320 : 480) << file;
  }
}

// The application scenes the docs point to (docs/gallery.md, docs/cameras.md) are all there and
// are picked up by the smoke test above.
TEST(SceneFiles, ApplicationsAreFound) {
  const char* const expected[] = {"domemaster",
                                  "omnimax",
                                  "vr_ods",
                                  "light_field_quilt",
                                  "integral_image",
                                  "mercator",
                                  "lambert",
                                  "focus_context",
                                  "coin_animation",
                                  "bspline_animation",
                                  "matched_lens",
                                  "isometric",
                                  "fisheye_180",
                                  "light_probe",
                                  "matched_pinhole",
                                  "panorama_360",
                                  "cylindrical_panorama",
                                  "little_planet",
                                  "panini_wide",
                                  "cubemap",
                                  "pushbroom",
                                  "crossed_slits",
                                  "omnimax_dome",
                                  "scattered_surface",
                                  "dome_pulled",
                                  "calibrated_lens",
                                  "formfactor_room",
                                  "radiosity_spheres"};
  const std::vector<SceneFile> files = scene_files();
  for (const char* name : expected) {
    const bool found = std::any_of(files.begin(), files.end(), [&](const SceneFile& f) {
      return f.group == "apps" && f.path.stem() == name;
    });
    EXPECT_TRUE(found) << "examples/apps/" << name << ".toml is missing from the smoke test";
  }
}

// Every preset has a bundled scene that uses it, listed in the "Example scenes" table of
// docs/cameras.md.
TEST(SceneFiles, EveryPresetHasAnExampleScene) {
  const auto read = [](const fs::path& p) {
    std::ifstream f(p);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
  };
  std::vector<std::pair<fs::path, std::string>> texts;
  for (const SceneFile& f : scene_files()) texts.emplace_back(f.path, read(f.path));
  const std::string docs = read(test::source_dir() / "docs" / "cameras.md");
  const size_t section = docs.find("## Example scenes");
  ASSERT_NE(section, std::string::npos) << "docs/cameras.md has no \"Example scenes\" section";
  for (const PresetInfo& p : camera_presets()) {
    const std::string use = "preset = \"" + std::string(p.name) + "\"";
    const auto it = std::find_if(texts.begin(), texts.end(), [&](const auto& t) {
      return t.second.find(use) != std::string::npos;
    });
    EXPECT_NE(it, texts.end()) << "no scene in examples/ uses " << use;
    const std::string row = "| " + std::string(p.name) + " | [examples/";
    EXPECT_NE(docs.find(row, section), std::string::npos)
        << "docs/cameras.md, Example scenes: no row for " << p.name;
  }
}

}  // namespace
}  // namespace anamorph
