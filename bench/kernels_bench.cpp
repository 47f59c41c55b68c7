// Hot kernels of the renderer: packet vs single-ray tracing, texture and BSDF evaluation, RNG.
#include <benchmark/benchmark.h>

#include <cmath>

#include "accel/accel.h"
#include "material/bsdf.h"
#include "material/material_kinds.h"
#include "math/rng.h"
#include "scene/scene_loader.h"

namespace anamorph {

namespace {

// A finely tessellated sphere mesh, so the benchmark needs no external files.
Scene tessellated_sphere_scene(int n) {
  Scene s;
  s.materials.push_back(make_material("name = \"grey\""));
  Prototype p;
  TriangleMesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= 2 * n; ++i) {
      const double th = kPi * j / n, ph = kPi * i / n;
      m.positions.push_back(
          Vec3f(Vec3{std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph)}));
    }
  const int row = 2 * n + 1;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < 2 * n; ++i) {
      const uint32_t a = uint32_t(j * row + i), b = a + 1, c = a + uint32_t(row), d = c + 1;
      m.indices.insert(m.indices.end(), {a, c, b, b, c, d});
    }
  p.meshes.push_back(std::move(m));
  s.prototypes.push_back(std::move(p));
  s.instances.push_back(Instance{0, Transform(), "sphere", {}});
  return s;
}

std::vector<Ray> primary_rays(int w, int h) {
  std::vector<Ray> rays;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Vec3 d = normalize(Vec3{(x + 0.5) / w * 2.4 - 1.2, 1.2 - (y + 0.5) / h * 2.4, -1});
      rays.push_back(Ray{{0, 0, 3}, d, 0, kInf});
    }
  return rays;
}

// Rays in 4x4 pixel blocks, the renderer's packet order.
std::vector<Ray> blocked(const std::vector<Ray>& rays, int w, int h) {
  std::vector<Ray> out;
  for (int by = 0; by < h; by += 4)
    for (int bx = 0; bx < w; bx += 4)
      for (int k = 0; k < 16; ++k) out.push_back(rays[size_t((by + k / 4) * w + bx + k % 4)]);
  return out;
}

}  // namespace

static void BM_TraceSingle(benchmark::State& state) {
  const Scene s = tessellated_sphere_scene(200);
  const Accel accel(s);
  const auto rays = primary_rays(256, 256);
  for (auto _ : state) {
    int hits = 0;
    Hit h;
    for (const Ray& r : rays) hits += accel.intersect(r, &h);
    benchmark::DoNotOptimize(hits);
  }
  state.SetItemsProcessed(state.iterations() * int64_t(rays.size()));
}
BENCHMARK(BM_TraceSingle)->Unit(benchmark::kMillisecond);

static void BM_TracePacket16(benchmark::State& state) {
  const Scene s = tessellated_sphere_scene(200);
  const Accel accel(s);
  const auto rays = blocked(primary_rays(256, 256), 256, 256);
  bool valid[16], found[16];
  Hit hits[16];
  std::fill(valid, valid + 16, true);
  for (auto _ : state) {
    int n = 0;
    for (size_t i = 0; i < rays.size(); i += 16) {
      accel.intersect16(&rays[i], valid, hits, found);
      n += found[0];
    }
    benchmark::DoNotOptimize(n);
  }
  state.SetItemsProcessed(state.iterations() * int64_t(rays.size()));
}
BENCHMARK(BM_TracePacket16)->Unit(benchmark::kMillisecond);

static void BM_CheckerTexture(benchmark::State& state) {
  Texture t;
  t.kind = Texture::Kind::Checker;
  t.space = Texture::Space::World;
  TexCoord tc;
  tc.n_world = {0, 1, 0};
  tc.dpdx = {0.01, 0, 0};
  tc.dpdy = {0, 0, 0.01};
  double x = 0;
  for (auto _ : state) {
    tc.p_world = {x, 0, 0.37 * x};
    x += 0.013;
    benchmark::DoNotOptimize(t.eval(tc));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_CheckerTexture);

static void BM_BsdfSampleGgx(benchmark::State& state) {
  Bsdf b;
  b.diffuse = Color(0.3);
  b.ggx_f0 = Color(0.04);
  b.ggx_alpha = 0.2;
  Rng rng(1, 2);
  const Vec3 wo = normalize(Vec3{0.3, 0.2, 0.9});
  for (auto _ : state) {
    BsdfSample s;
    benchmark::DoNotOptimize(b.sample(wo, {rng.uniform(), rng.uniform()}, rng.uniform(), &s));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_BsdfSampleGgx);

static void BM_RngForSample(benchmark::State& state) {
  uint32_t i = 0;
  for (auto _ : state) {
    Rng r = Rng::for_sample(i & 1023, i >> 10, 3, 42);
    benchmark::DoNotOptimize(r.uniform());
    ++i;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_RngForSample);

}  // namespace anamorph
