// `anamorph bench`: render the same frame repeatedly and report render-only Mrays/s, the way
// Embree's viewer --benchmark does (warm-up frames skipped), so the two can be compared.
#include <fmt/format.h>

#include <algorithm>
#include <numeric>

#include "app/common.h"
#include "render/renderer.h"

namespace anamorph::app {

namespace {

struct BenchArgs {
  SceneOptions scene;
  std::vector<int> frames{3, 10};
  std::optional<int> threads;
};

int run(const BenchArgs& a) {
  const Scene scene = load(a.scene);
  const Renderer renderer(scene);
  RenderOptions opt;
  opt.threads = a.threads.value_or(0);
  opt.progressive = false;
  const int warm = a.frames[0], measured = a.frames[1];
  std::vector<double> mrays;
  // One film for every frame, as a viewer reuses its frame buffer (a new 100 MB film per frame
  // would time the kernel's page clearing). Each render overwrites every pixel with its first
  // sample, so the film needs no clearing in between either, as the viewer's frame buffer.
  Film film(scene.render.width, scene.render.height, {});
  for (int f = 0; f < warm + measured; ++f) {
    const RenderStats st = renderer.render(film, opt);
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
  return kOk;
}

}  // namespace

void add_bench(CLI::App& app, std::function<int()>& runner) {
  auto a = std::make_shared<BenchArgs>();
  CLI::App* cmd =
      app.add_subcommand("bench", "Render a scene repeatedly and report render-only Mrays/s");
  a->scene.add_to(*cmd);
  cmd->add_option("--frames", a->frames, "Warm-up and measured frames (default 3 10)")
      ->expected(2)
      ->check(CLI::Range(0, 100000));
  cmd->add_option("--threads", a->threads, "Worker threads (default: all cores)")
      ->check(CLI::Range(1, 1024));
  cmd->callback([a, &runner] {
    if (a->frames[1] < 1)
      throw CLI::ValidationError("--frames", "need at least one measured frame");
    runner = [a] { return run(*a); };
  });
}

}  // namespace anamorph::app
