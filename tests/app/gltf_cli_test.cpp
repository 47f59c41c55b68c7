// `anamorph render scene.glb` and `anamorph info scene.glb` from the command line (issue 34):
// no scene file, --camera and --env changing what glTF cannot say.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include <fmt/format.h>

#include "cli_util.h"
#include "io/image_io.h"
#include "same_images.h"
#include "test_util.h"

namespace anamorph {
namespace {

namespace fs = std::filesystem;

std::string glb(const std::string& name) {
  return fmt::format("'{}'", (test::data_dir() / "gltf/blender" / (name + ".glb")).string());
}

bool has(const std::string& text, const std::string& needle) {
  return text.find(needle) != std::string::npos;
}

TEST(GltfCli, InfoListsWhatWasReadAndWhatWasNot) {
  const test::CliResult r = test::run_cli("info " + glb("studio"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(has(r.out, "640x480, 64 spp (stratified), integrator path, max_depth 9")) << r.out;
  EXPECT_TRUE(has(r.out, "glTF perspective camera 'camera'")) << r.out;
  EXPECT_TRUE(has(r.out, "5 mesh(es), 5 material(s), 1 texture(s)")) << r.out;
  EXPECT_TRUE(has(r.out, "1 camera(s), 3 light(s), 0 animation(s)")) << r.out;
  EXPECT_TRUE(has(r.out, "extension KHR_lights_punctual (required): read")) << r.out;
  EXPECT_TRUE(has(r.out, "extension KHR_materials_specular: read")) << r.out;
  const test::CliResult a = test::run_cli("info " + glb("skinned_morph"));
  ASSERT_EQ(a.code, 0) << a.out;
  EXPECT_TRUE(has(a.out, "1 skin(s), 2 morph target(s)")) << a.out;
}

TEST(GltfCli, CameraAndEnvOptions) {
  const test::CliResult r =
      test::run_cli("info " + glb("studio") + " --camera fisheye --env 0.1,0.2,0.3");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(has(r.out, "at glTF camera 'camera'")) << r.out;
  EXPECT_TRUE(has(r.out, "environment constant colour")) << r.out;
  // An environment image is read (and listed among the run's inputs); a camera index too.
  const fs::path env = test::data_dir() / "gltf/blender/textures/checker.png";
  const test::CliResult e =
      test::run_cli("info " + glb("studio") + " --camera 0 --env '" + env.string() + "'");
  ASSERT_EQ(e.code, 0) << e.out;
  EXPECT_TRUE(has(e.out, "environment image")) << e.out;
  EXPECT_TRUE(has(e.out, env.string())) << e.out;
  const test::CliResult bad = test::run_cli("info " + glb("studio") + " --camera 3");
  EXPECT_EQ(bad.code, 2) << bad.out;
  EXPECT_TRUE(has(bad.out, "gltf_camera")) << bad.out;
}

TEST(GltfCli, RendersAGlbWithoutASceneFile) {
  const fs::path out =
      fs::temp_directory_path() / ("anamorph_gltf_cli_" + std::to_string(getpid()) + ".png");
  const test::CliResult r = test::run_cli(
      "render " + glb("point_only") + " --width 32 --set render.spp=2 -o '" + out.string() + "'");
  ASSERT_EQ(r.code, 0) << r.out;
  const Image img = read_image(out, false);
  fs::remove(out);
  EXPECT_EQ(img.width, 32);
  EXPECT_EQ(img.height, 24);  // the camera's 4:3
  double sum = 0;
  for (float v : img.pixels) sum += v;
  EXPECT_GT(sum, 0) << "black image";
}

// A sequence of an animated file poses the first frame's scene again at each frame, moving its
// instances and rebuilding only deformed meshes and the top level (Renderer::repose): the frames
// must be the bits of each frame rendered alone. animated.glb moves and turns objects and a
// light; skinned_morph.glb deforms a skinned and a morphed mesh.
TEST(GltfCli, AnimatedSequenceEqualsStills) {
  const fs::path dir =
      fs::temp_directory_path() / ("anamorph_gltf_frames_" + std::to_string(getpid()));
  fs::create_directories(dir);
  for (const std::string name : {"animated", "skinned_morph"}) {
    const std::string common = "render " + glb(name) + " -q --width 40 --set render.spp=2 ";
    const std::string seq = (dir / (name + "_seq_%d.exr")).string();
    const test::CliResult r = test::run_cli(common + "--frames 1:3 -o '" + seq + "'");
    ASSERT_EQ(r.code, 0) << r.out;
    for (int f = 2; f <= 3; ++f) {
      const std::string still = (dir / (name + "_still_%d.exr")).string();
      const std::string range = fmt::format("--frames {}:{} ", f, f);
      ASSERT_EQ(test::run_cli(common + range + "-o '" + still + "'").code, 0);
      SCOPED_TRACE(name + " frame " + std::to_string(f));
      test::expect_same_exr(dir / fmt::format("{}_still_{}.exr", name, f),
                            dir / fmt::format("{}_seq_{}.exr", name, f));
    }
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace anamorph
