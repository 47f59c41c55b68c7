// Ray generation cost per camera, for a 1920x1080 image (one ray per pixel center).
#include <benchmark/benchmark.h>

#include "camera/presets.h"

namespace anamorph {

static void BM_Perspective1080p(benchmark::State& state) {
  ParamValues v;
  v.set("look_from", Vec3{0, 0, 0});
  v.set("look_at", Vec3{0, 0, -1});
  v.set("up", Vec3{0, 1, 0});
  v.set("fov", 60.0);
  v.set("fov_axis", std::string("horizontal"));
  v.set("lens_shift", Vec2{0, 0});
  const VirtualCamera cam(find_preset("perspective")->create(v, {1920, 1080}));
  for (auto _ : state) {
    double acc = 0;
    for (int y = 0; y < 1080; ++y)
      for (int x = 0; x < 1920; ++x) {
        const auto r = cam.generate({{(x + 0.5) / 1920, (y + 0.5) / 1080}});
        acc += r->dir.x;
      }
    benchmark::DoNotOptimize(acc);
  }
  state.SetItemsProcessed(state.iterations() * 1920 * 1080);
}
BENCHMARK(BM_Perspective1080p)->Unit(benchmark::kMillisecond);

}  // namespace anamorph
