// Every bundled scene (examples/, examples/paper, examples/apps) opened in the editor as a user
// would: its preview shows a frame, the camera views answer, and the text it would save without
// an edit is the file itself, byte for byte.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "server/editor.h"
#include "test_util.h"

namespace anamorph::test {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> example_scenes() {
  std::vector<std::string> files;
  for (const char* dir : {"examples", "examples/paper", "examples/apps"})
    for (const auto& e : fs::directory_iterator(fs::path(ANAMORPH_SOURCE_DIR) / dir))
      if (e.path().extension() == ".toml")
        files.push_back(fs::relative(e.path(), ANAMORPH_SOURCE_DIR));
  std::sort(files.begin(), files.end());
  return files;
}

class EveryExample : public ::testing::TestWithParam<std::string> {};

TEST_P(EveryExample, OpensShowsAFrameAndSavesItsOwnText) {
  const fs::path file = fs::path(ANAMORPH_SOURCE_DIR) / GetParam();
  server::Editor editor(file, [](const server::FinalRenderJob&) {});
  // The first frame (the quarter-size one is enough: it is the camera as it will render).
  const auto frame = editor.preview().wait_frame(0, 120, {});
  ASSERT_TRUE(frame) << "no preview frame: " << editor.preview().error();
  EXPECT_EQ(frame->rgba.size(), size_t(frame->width) * frame->height * 4);
  EXPECT_EQ(frame->version, 1);

  const auto map = editor.magnification(16, 9, 1);
  ASSERT_TRUE(map);
  ASSERT_EQ(map->size(), 16u * 9u);
  for (float m : *map) EXPECT_TRUE(std::isnan(m) || (std::isfinite(m) && m > 0)) << m;
  const auto rays = editor.ray_overview(4, 3, 1);
  ASSERT_TRUE(rays);
  for (size_t i = 0; i < rays->dir.size(); ++i)
    if (rays->valid[i]) {
      EXPECT_NEAR(length(rays->dir[i]), 1.0, 1e-9) << "ray " << i;
    }

  std::ifstream in(file, std::ios::binary);
  std::stringstream original;
  original << in.rdbuf();
  const server::SavedText saved = server::saved_text(original.str(), toml::parse(original.str()));
  EXPECT_FALSE(saved.normalized);
  EXPECT_EQ(saved.text, original.str()) << "an unedited scene is saved as it was";
  EXPECT_EQ(editor.state()["text"].get<std::string>(), original.str());
}

INSTANTIATE_TEST_SUITE_P(Scenes, EveryExample, ::testing::ValuesIn(example_scenes()),
                         [](const ::testing::TestParamInfo<std::string>& p) {
                           std::string n = p.param;
                           for (char& c : n)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return n;
                         });

}  // namespace
}  // namespace anamorph::test
