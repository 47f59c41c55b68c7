// Clear limits: a render's memory is estimated before anything is allocated, and a frame the
// machine cannot hold is refused with exit 2, the figures and no output file.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "app/cli_util.h"
#include "render/memory_estimate.h"
#include "render/tile_buffer.h"
#include "scene/scene.h"
#include "test_util.h"

namespace anamorph {
namespace {

namespace fs = std::filesystem;

std::string demo_scene() { return (test::source_dir() / "examples/apps/domemaster.toml").string(); }

// The layouts of docs/architecture.md: a film is 32 bytes a pixel plus the AOV floats; streamed
// tiles cost the tiles in flight and a few strips, independent of the frame's height.
TEST(MemoryEstimate, FilmAndStreamedFramesCostWhatTheLayoutSays) {
  const Scene scene;  // no geometry
  RenderShape film;
  film.width = 1000;
  film.height = 500;
  film.aov_floats = 6;
  film.whole_film = true;
  film.active_mask = true;
  film.strip_bytes_per_pixel = 16 + 4 * 6;  // an EXR with the AOVs
  const MemoryNeed f = estimate_render_memory(scene, film);
  ASSERT_FALSE(f.parts.empty());
  EXPECT_EQ(f.parts[0].second, 1000u * 500u * (32u + 24u)) << f.describe();
  EXPECT_EQ(f.parts[1].second, 1000u * 500u) << f.describe();
  EXPECT_EQ(sizeof(PixelSum), 32u);

  RenderShape streamed = film;
  streamed.whole_film = streamed.active_mask = false;
  streamed.width = streamed.height = 16384;
  streamed.threads = 2;
  const uint64_t tall = estimate_render_memory(scene, streamed).total();
  streamed.height = 64;
  const uint64_t short_one = estimate_render_memory(scene, streamed).total();
  // Only the tile table grows with the height (a pointer and a flag per tile).
  EXPECT_LT(tall - short_one, uint64_t(512) * 512 * 16) << tall << " vs " << short_one;
  EXPECT_LT(tall, uint64_t(300) << 20) << estimate_render_memory(scene, streamed).describe();
}

TEST(MemoryEstimate, AvailableMemoryIsReadAndBytesAreFormatted) {
  EXPECT_GT(available_memory(), uint64_t(16) << 20);
  EXPECT_EQ(format_bytes(512), "512 B");
  EXPECT_EQ(format_bytes(uint64_t(3) << 29), "1.5 GiB");
}

// 65536^2 with per-pixel adaptive sampling keeps a film of 65536^2 x 33 B = 141 GB: refused at
// once, before any allocation, with exit 2 and no file.
TEST(MemoryLimit, AFrameTooBigForTheMachineIsRefused) {
  const uint64_t film = uint64_t(65536) * 65536 * 33;
  if (available_memory() > film) GTEST_SKIP() << "this machine has room for a 141 GB film";
  const fs::path out =
      fs::temp_directory_path() / ("anamorph_mem_" + std::to_string(getpid()) + ".exr");
  const test::CliResult r = test::run_cli("render " + demo_scene() +
                                          " --width 65536 --height 65536 --integrator path --set "
                                          "render.antialias=\\\"pixel\\\" -o " +
                                          out.string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("this render needs about"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("film (65536 x 65536 pixels x 32 B)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("sample uniformly"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("bad_alloc"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(out));
}

// An address-space limit (ulimit -v) counts: 16384^2 in a film (8.8 GB) does not fit in 4 GB.
// (Not under AddressSanitizer, which reserves terabytes of address space at start.)
TEST(MemoryLimit, AnAddressSpaceLimitIsRespected) {
#if defined(ANAMORPH_ASAN) || defined(ANAMORPH_TSAN)
  GTEST_SKIP() << "sanitizers need unlimited address space";
#else
  const fs::path out =
      fs::temp_directory_path() / ("anamorph_mem_" + std::to_string(getpid()) + ".exr");
  const test::CliResult r = test::run_shell(
      "ulimit -v 4000000; '" + test::binary().string() + "' render " + demo_scene() +
      " --width 16384 --height 16384 --integrator path --set render.antialias=\\\"pixel\\\" -o " +
      out.string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("this render needs about 8."), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(out));
  // Streamed, the same frame fits: uniform sampling needs tiles and strips only. (Checked by the
  // estimate, not rendered: it would take minutes.)
  RenderShape shape;
  shape.width = shape.height = 16384;
  shape.strip_bytes_per_pixel = 16;  // an EXR
  shape.threads = 2;
  EXPECT_LT(estimate_render_memory(Scene{}, shape).total(), uint64_t(100) << 20);
#endif
}

}  // namespace
}  // namespace anamorph
