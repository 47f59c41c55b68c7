// A NUL in a file name: every reader and writer refuses it, naming what the system would have
// read instead (the name cut at the NUL), and nothing under the cut name is read or written.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "io/image_io.h"
#include "io/read_file.h"
#include "scene/loaders.h"
#include "scene/scene_loader.h"
#include "scene/toml_reader.h"

namespace anamorph {
namespace {

namespace fs = std::filesystem;
using namespace std::string_literals;

struct Dir {
  fs::path dir = fs::temp_directory_path() / ("anamorph_nul_" + std::to_string(getpid()));
  Dir() { fs::create_directories(dir); }
  ~Dir() { fs::remove_all(dir); }
};

// The message of what `f` throws (of type E), or a failure.
template <class E, class F>
std::string error_of(F f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error";
  return {};
}

TEST(NulInPath, ReadersAndWritersRefuseItAndLeaveTheCutNameAlone) {
  const Dir d;
  const fs::path cut = d.dir / "a.png";
  OutputImage img;
  img.width = img.height = 2;
  img.layers.push_back({"", {"R", "G", "B", "A"}, std::vector<float>(16, 0.5f)});
  write_png(cut, img);  // the file a truncated name would reach
  const auto before = fs::last_write_time(cut);
  const std::string bad = cut.string() + "\0.exr"s;
  const std::string want = "contains a NUL character (the system would read it as '";
  EXPECT_NE(error_of<ImageReadError>([&] { read_image(bad); }).find(want), std::string::npos);
  EXPECT_NE(error_of<ImageIoError>([&] { write_png(bad, img); }).find(want), std::string::npos);
  EXPECT_NE(error_of<ImageIoError>([&] { write_exr(bad, img); }).find(want), std::string::npos);
  EXPECT_NE(error_of<LoadError>([&] { load_model(bad); }).find(want), std::string::npos);
  const std::string scene = error_of<SceneError>([&] { load_scene(bad); });
  EXPECT_NE(scene.find("a.png\\x00.exr: the file name contains a NUL"), std::string::npos) << scene;
  std::vector<unsigned char> bytes;
  const auto failure = read_whole_file(bad, &bytes, kTextInput);
  ASSERT_TRUE(failure.has_value());
  EXPECT_EQ(failure->error, EINVAL);
  EXPECT_TRUE(bytes.empty());
  EXPECT_EQ(fs::last_write_time(cut), before) << "the file at the cut name was written";
  // The messages carry no raw NUL (what() would end there for every reader of it).
  EXPECT_EQ(error_of<ImageIoError>([&] { write_png(bad, img); }).find('\0'), std::string::npos);
}

}  // namespace
}  // namespace anamorph
