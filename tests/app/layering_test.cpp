// The source folders form layers: a folder includes headers of its own and of the folders below
// it, never of one above (math < params, model, io < camera, material < scene < accel < render <
// dist, solve < server < app: the editor's pin tool solves with src/solve; the denoiser sits
// beside them: math < denoise < render; warp's pixels and textures: io, camera, plugins < warp <
// app).
// A lower folder that reached up would drag the loaders into the camera, or the scene into image
// I/O, and every user of the lower one would need the higher one too.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <string>

#include "test_util.h"

namespace anamorph {
namespace {

namespace fs = std::filesystem;

const std::map<std::string, std::set<std::string>> kMayInclude = {
    {"math", {"math"}},
    {"params", {"math", "params"}},
    {"model", {"math", "model"}},
    {"io", {"math", "io"}},
    {"denoise", {"math", "denoise"}},
    {"camera", {"math", "params", "model", "camera"}},
    {"material", {"math", "params", "model", "io", "material"}},
    // anamorph warp's pixels and textures (the OpenImageIO plugin's C interface among them).
    {"warp", {"math", "params", "model", "io", "camera", "plugins", "warp"}},
    {"scene", {"math", "params", "model", "io", "camera", "material", "scene"}},
    {"accel", {"math", "params", "model", "io", "camera", "material", "scene", "accel"}},
    {"render",
     {"math", "params", "model", "io", "denoise", "camera", "material", "scene", "accel",
      "render"}},
    {"dist",
     {"math", "params", "model", "io", "denoise", "camera", "material", "scene", "accel", "render",
      "dist"}},
    // The camera solver (`anamorph solve`, the editor's pins): beside dist, below the server.
    {"solve",
     {"math", "params", "model", "io", "denoise", "camera", "material", "scene", "accel", "render",
      "solve"}},
    {"server",
     {"math", "params", "model", "io", "denoise", "camera", "material", "scene", "accel", "render",
      "solve", "server"}},
    // Plugins the program loads with dlopen (a C interface); they include only their own.
    {"plugins", {"plugins"}},
    {"app",
     {"math", "params", "model", "io", "denoise", "camera", "material", "scene", "accel", "render",
      "dist", "server", "solve", "plugins", "warp", "app"}},
};

TEST(Layering, NoFolderIncludesAHigherOne) {
  const fs::path src = test::source_dir() / "src";
  const std::regex include(R"re(^\s*#\s*include\s+"([a-z_]+)/)re");
  int files = 0;
  for (const auto& e : fs::recursive_directory_iterator(src)) {
    const std::string ext = e.path().extension().string();
    if (ext != ".h" && ext != ".cpp") continue;
    const std::string folder = fs::relative(e.path(), src).begin()->string();
    const auto allowed = kMayInclude.find(folder);
    ASSERT_NE(allowed, kMayInclude.end()) << "folder src/" << folder << " has no layer here";
    ++files;
    std::ifstream in(e.path());
    int line_no = 0;
    for (std::string line; std::getline(in, line);) {
      ++line_no;
      std::smatch m;
      if (!std::regex_search(line, m, include)) continue;
      EXPECT_TRUE(allowed->second.count(m[1].str()))
          << e.path().string() << ":" << line_no << ": src/" << folder << " includes " << m[1].str()
          << "/, a layer above it";
    }
  }
  EXPECT_GT(files, 100);
}

}  // namespace
}  // namespace anamorph
