// Origin/direction function cost per ray at 1920x1080 (one sample per pixel center): a bicubic
// B-spline org with dir = normal, evaluated one sample at a time (eval) and in the renderer's
// 4x4 packets (eval_batch, which shares each row's curve among the packets along it), plus a
// NURBS and a sphere for comparison.
#include <benchmark/benchmark.h>

#include <cmath>
#include <string>
#include <vector>

#include "camera/functions.h"

namespace anamorph {

namespace {

constexpr int kW = 1920, kH = 1080;  // multiples of 4: whole packets

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

// 4x4 packets of pixel centers, as the renderer asks for them.
void eval_batch_image(benchmark::State& state, const OrgFunction& org, const DirFunction& dir) {
  for (auto _ : state) {
    double acc = 0;
    double u[kCameraBatch], v[kCameraBatch];
    SurfaceBatch s;
    DirBatch d;
    for (int y0 = 0; y0 < kH; y0 += 4)
      for (int x0 = 0; x0 < kW; x0 += 4) {
        for (int k = 0; k < kCameraBatch; ++k)
          u[k] = (x0 + k % 4 + 0.5) / kW, v[k] = (y0 + k / 4 + 0.5) / kH;
        org.eval_batch(u, v, kCameraBatch, &s);
        dir.eval_batch(u, v, kCameraBatch, s, &d);
        for (int k = 0; k < kCameraBatch; ++k) acc += d.ok[k] ? d.d[0][k] : 0.0;
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
static void BM_BSplineNormal_EvalBatch(benchmark::State& state) {
  eval_batch_image(state, *make_org("bspline", kBicubic), *make_dir("normal"));
}
static void BM_NurbsNormal_Eval(benchmark::State& state) {
  eval_image(state, *make_org("nurbs", kNurbs), *make_dir("normal"));
}
static void BM_NurbsNormal_EvalBatch(benchmark::State& state) {
  eval_batch_image(state, *make_org("nurbs", kNurbs), *make_dir("normal"));
}
static void BM_SphereNormal_Eval(benchmark::State& state) {
  eval_image(state, *make_org("sphere"), *make_dir("normal"));
}
BENCHMARK(BM_BSplineNormal_Eval)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BSplineNormal_EvalBatch)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_NurbsNormal_Eval)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_NurbsNormal_EvalBatch)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SphereNormal_Eval)->Unit(benchmark::kMillisecond);

}  // namespace anamorph
