// Origin/direction function cost per ray at 1920x1080 (one sample per pixel center): a bicubic
// B-spline org with dir = normal, evaluated one sample at a time (eval) and per 64x64 tile
// (eval_grid, which shares basis functions along rows and columns), plus a NURBS and a sphere
// for comparison.
#include <benchmark/benchmark.h>

#include <cmath>
#include <string>
#include <vector>

#include "camera/functions.h"

namespace anamorph {

namespace {

constexpr int kW = 1920, kH = 1080, kTile = 64;

// An 8x8 wavy control net (5x5 knot spans per direction at degree 3).
std::string net(bool weights) {
  std::string pts = "points = [", w = "weights = [";
  for (int j = 0; j < 8; ++j) {
    pts += j ? ", [" : "[";
    w += j ? ", [" : "[";
    for (int i = 0; i < 8; ++i) {
      pts += (i ? ", [" : "[") + std::to_string(i * 0.5 - 1.75) + ", " +
             std::to_string(1.75 - j * 0.5) + ", " + std::to_string(-2 + 0.3 * std::sin(i + j)) +
             "]";
      w += (i ? ", " : "") + std::to_string(0.7 + 0.1 * ((i + 2 * j) % 4));
    }
    pts += "]";
    w += "]";
  }
  return pts + "]\n" + (weights ? w + "]\n" : "");
}

void eval_image(benchmark::State& state, const OrgFunction& org, const DirFunction& dir) {
  for (auto _ : state) {
    double acc = 0;
    SurfaceSample s;
    DirSample d;
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        const Vec2 uv{(x + 0.5) / kW, (y + 0.5) / kH};
        if (org.eval(uv, &s) && dir.eval(uv, s, &d)) acc += d.d.x;
      }
    benchmark::DoNotOptimize(acc);
  }
  state.SetItemsProcessed(state.iterations() * kW * kH);
}

void eval_grid_image(benchmark::State& state, const OrgFunction& org, const DirFunction& dir) {
  std::vector<SurfaceSample> tile(size_t(kTile) * kTile);
  std::vector<double> us(kTile), vs(kTile);
  for (auto _ : state) {
    double acc = 0;
    DirSample d;
    for (int y0 = 0; y0 < kH; y0 += kTile)
      for (int x0 = 0; x0 < kW; x0 += kTile) {
        const int nx = std::min(kTile, kW - x0), ny = std::min(kTile, kH - y0);
        for (int i = 0; i < nx; ++i) us[size_t(i)] = (x0 + i + 0.5) / kW;
        for (int j = 0; j < ny; ++j) vs[size_t(j)] = (y0 + j + 0.5) / kH;
        org.eval_grid({us.data(), size_t(nx)}, {vs.data(), size_t(ny)}, tile.data());
        for (int j = 0; j < ny; ++j)
          for (int i = 0; i < nx; ++i) {
            const SurfaceSample& s = tile[size_t(j) * size_t(nx) + size_t(i)];
            if (dir.eval({us[size_t(i)], vs[size_t(j)]}, s, &d)) acc += d.d.x;
          }
      }
    benchmark::DoNotOptimize(acc);
  }
  state.SetItemsProcessed(state.iterations() * kW * kH);
}

const std::string kBicubic = net(false) + "degree_u = 3\ndegree_v = 3\n";
const std::string kNurbs = net(true) + "degree_u = 3\ndegree_v = 3\n";

}  // namespace

static void BM_BSplineNormal_Eval(benchmark::State& state) {
  eval_image(state, *make_org("bspline", kBicubic), *make_dir("normal"));
}
static void BM_BSplineNormal_EvalGrid(benchmark::State& state) {
  eval_grid_image(state, *make_org("bspline", kBicubic), *make_dir("normal"));
}
static void BM_NurbsNormal_Eval(benchmark::State& state) {
  eval_image(state, *make_org("nurbs", kNurbs), *make_dir("normal"));
}
static void BM_NurbsNormal_EvalGrid(benchmark::State& state) {
  eval_grid_image(state, *make_org("nurbs", kNurbs), *make_dir("normal"));
}
static void BM_SphereNormal_Eval(benchmark::State& state) {
  eval_image(state, *make_org("sphere"), *make_dir("normal"));
}
BENCHMARK(BM_BSplineNormal_Eval)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BSplineNormal_EvalGrid)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_NurbsNormal_Eval)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_NurbsNormal_EvalGrid)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SphereNormal_Eval)->Unit(benchmark::kMillisecond);

}  // namespace anamorph
