// `anamorph bench`: render the same frame repeatedly and report render-only Mrays/s, the way
// Embree's viewer --benchmark does (warm-up frames skipped), so the two can be compared.
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdlib>
#include <memory>
#include <numeric>

#include "app/common.h"
#include "app/thread_option.h"
#include "math/simd.h"
#include "render/frame_output.h"
#include "render/renderer.h"

namespace anamorph::app {

namespace {

struct BenchArgs {
  SceneOptions scene;
  int warm_up = 3, measure = 10;
  std::vector<std::string> frames;  // the old name of --warm-up W --measure M
  std::optional<int> threads;
};

// `--frames W M`, bench's name until `render --frames A:B` made it mean something else: still
// taken, with a warning; anything else is an error that says what to write.
void take_old_frames(BenchArgs& a) {
  const auto count = [](const std::string& t, int* v) {
    char* end = nullptr;
    const long x = std::strtol(t.c_str(), &end, 10);
    if (t.empty() || *end || x < 0 || x > 100000) return false;
    *v = int(x);
    return true;
  };
  if (a.frames.size() != 2 || !count(a.frames[0], &a.warm_up) || !count(a.frames[1], &a.measure))
    throw CLI::ValidationError(
        "--frames",
        "bench takes --warm-up N --measure N (frames rendered before measuring, and "
        "measured); --frames A:B picks animation frames in `render` only");
  fmt::print(stderr,
             "warning: bench --frames {} {} is deprecated: write --warm-up {} --measure {}\n",
             a.warm_up, a.measure, a.warm_up, a.measure);
}

int run(const BenchArgs& a) {
  const Scene scene = load(a.scene);
  const Renderer renderer(scene);
  RenderOptions opt;
  opt.threads = a.threads.value_or(0);
  const int warm = a.warm_up, measured = a.measure;
  std::vector<double> mrays;
  // One 8-bit RGBA frame buffer for every frame, as the viewer keeps one: each finished tile is
  // resolved straight into it (render/frame_output.h: resolve_rgba8) and its buffer reused for
  // the thread's next tile, so memory is the frame buffer and the tiles in flight.
  const int W = scene.render.width, H = scene.render.height;
  const TileGrid grid(W, H, scene.render.tile_size);
  std::vector<unsigned char> frame(size_t(W) * size_t(H) * 4);
  const TileSink to_frame = [&](size_t, std::unique_ptr<TileBuffer>& tile) {
    const TileRect& r = tile->rect();
    resolve_rgba8(*tile, &frame[(size_t(r.y0) * size_t(W) + size_t(r.x0)) * 4], size_t(W) * 4);
  };
  // Per-pixel adaptive sampling looks across tiles: that one renders into a film.
  std::unique_ptr<Film> film;
  if (!Renderer::streams(scene.render)) film = std::make_unique<Film>(W, H, std::vector<Aov>{});
  for (int f = 0; f < warm + measured; ++f) {
    const RenderStats st =
        film ? renderer.render(*film, opt) : renderer.render_tiles(grid, opt, {}, to_frame);
    if (f >= warm) mrays.push_back(st.mrays_per_second());
    fmt::print("frame {:3}: {:8.3f} Mrays/s{}\n", f, st.mrays_per_second(),
               f < warm ? " (warm-up)" : "");
  }
  std::sort(mrays.begin(), mrays.end());
  const double avg = std::accumulate(mrays.begin(), mrays.end(), 0.0) / double(mrays.size());
  fmt::print(
      "BENCHMARK_MRAYPS_MIN {:.4f}\nBENCHMARK_MRAYPS_MEDIAN {:.4f}\nBENCHMARK_MRAYPS_AVG {:.4f}\n"
      "BENCHMARK_MRAYPS_MAX {:.4f}\n",
      mrays.front(), mrays[mrays.size() / 2], avg, mrays.back());
  // The instruction set our kernels ran, and what Embree was told (math/simd.h; bench/compare).
  const char* embree = simd::embree_config();
  fmt::print("BENCHMARK_ISA {} (Embree: {})\n", simd::name(simd::active()),
             embree ? embree : "its own choice");
  return kOk;
}

}  // namespace

void add_bench(CLI::App& app, std::function<int()>& runner) {
  auto a = std::make_shared<BenchArgs>();
  CLI::App* cmd =
      app.add_subcommand("bench", "Render a scene repeatedly and report render-only Mrays/s");
  a->scene.add_to(*cmd);
  cmd->add_option("--warm-up", a->warm_up,
                  "Frames rendered before measuring (default 3), as Embree's viewer skips them")
      ->check(CLI::Range(0, 100000));
  cmd->add_option("--measure", a->measure, "Frames measured (default 10)")
      ->check(CLI::Range(1, 100000));
  cmd->add_option("--frames", a->frames, "Deprecated: --frames W M is --warm-up W --measure M")
      ->expected(1, 2);
  cmd->add_option("--threads", a->threads, "Worker threads (default: all cores)")
      ->check(thread_count_check());
  cmd->callback([a, &runner] {
    if (!a->frames.empty()) take_old_frames(*a);
    if (a->measure < 1) throw CLI::ValidationError("--frames", "need at least one measured frame");
    runner = [a] { return run(*a); };
  });
}

}  // namespace anamorph::app
