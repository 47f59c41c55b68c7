// Ray generation cost per camera for a 1920x1080 image (one ray per pixel center, one thread),
// against the cost of tracing the same number of primary rays through the Stanford bunny
// (when ../shared is present). docs/performance.md quotes the ratio.
#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "accel/accel.h"
#include "camera/presets.h"
#include "camera/ray_field.h"
#include "math/simd.h"
#include "scene/scene_loader.h"

namespace anamorph {

namespace {

constexpr int kW = 1920, kH = 1080;

void generate_all(benchmark::State& state, const Camera& cam) {
  for (auto _ : state) {
    double acc = 0;
    for (int y = 0; y < kH; ++y)
      for (int x = 0; x < kW; ++x) {
        const auto r = cam.generate({{(x + 0.5) / kW, (y + 0.5) / kH}});
        if (r) acc += r->dir.x;
      }
    benchmark::DoNotOptimize(acc);
  }
  state.SetItemsProcessed(state.iterations() * kW * kH);
}

// The renderer's way: 4x4 packets of pixel centers through generate_batch. The pixel-center
// coordinates are computed once, outside the timed loop, so the bench times the camera only.
void generate_packets(benchmark::State& state, const Camera& cam) {
  std::vector<double> us(kW), vs(kH);
  for (int x = 0; x < kW; ++x) us[size_t(x)] = (x + 0.5) / kW;
  for (int y = 0; y < kH; ++y) vs[size_t(y)] = (y + 0.5) / kH;
  CameraSample s[16];
  CameraRayBatch out;
  for (auto _ : state) {
    for (int y = 0; y < kH; y += 4)
      for (int x = 0; x < kW; x += 4) {
        for (int k = 0; k < 16; ++k) s[k].uv = {us[size_t(x + (k & 3))], vs[size_t(y + (k >> 2))]};
        cam.generate_batch(s, 16, &out);
        // Keep the rays without a dependent chain of additions (64 cycles a packet).
        benchmark::DoNotOptimize(&out);
        benchmark::ClobberMemory();
      }
  }
  state.SetItemsProcessed(state.iterations() * kW * kH);
}

// state.range(0): 0 = one ray at a time (generate), 1 = the renderer's packets (generate_batch).
void BM_Preset(benchmark::State& state, const char* name, const char* toml) {
  const VirtualCamera cam(make_preset(name, toml, {kW, kH}));
  if (state.range(0))
    generate_packets(state, cam);
  else
    generate_all(state, cam);
}

// A bicubic B-spline image surface (5x5 control points, gently curved) with normal directions.
const char* kSplineCamera =
    "[camera]\n"
    "org = { type = \"bspline\", points = ["
    "[[-2, 1.2, 0.3], [-1, 1.2, 0.1], [0, 1.2, 0], [1, 1.2, 0.1], [2, 1.2, 0.3]],"
    "[[-2, 0.6, 0.1], [-1, 0.6, 0], [0, 0.6, -0.1], [1, 0.6, 0], [2, 0.6, 0.1]],"
    "[[-2, 0, 0], [-1, 0, -0.1], [0, 0, -0.2], [1, 0, -0.1], [2, 0, 0]],"
    "[[-2, -0.6, 0.1], [-1, -0.6, 0], [0, -0.6, -0.1], [1, -0.6, 0], [2, -0.6, 0.1]],"
    "[[-2, -1.2, 0.3], [-1, -1.2, 0.1], [0, -1.2, 0], [1, -1.2, 0.1], [2, -1.2, 0.3]]] }\n"
    "dir = { type = \"normal\" }\n";

}  // namespace

// Every preset, with its defaults except where a bench needs a typical setting.
const bool kPresetsRegistered = [] {
  const std::pair<const char*, const char*> settings[] = {
      {"perspective", "fov = 60"},
      {"fisheye", "fov = 180"},
      {"dome", "tilt = 30"},
      {"opencv_pinhole", "fx = 1400\nfy = 1400\ncx = 960\ncy = 540\nk1 = -0.1\np1 = 0.001"},
      {"opencv_fisheye", "fx = 600\ncy = 540\nfy = 600\ncx = 960\nk1 = 0.05\nk2 = -0.01"}};
  for (const PresetInfo& p : camera_presets()) {
    const char* toml = "";
    for (const auto& [name, text] : settings)
      if (p.name == name) toml = text;
    benchmark::RegisterBenchmark(("BM_Preset/" + std::string(p.name)).c_str(), BM_Preset,
                                 p.name.data(), toml)
        ->ArgName("batch")
        ->Arg(0)
        ->Arg(1)
        ->Unit(benchmark::kMillisecond);
  }
  return true;
}();

static void BM_BSplineNormal(benchmark::State& state) {
  const Scene s = load_scene_from_string(kSplineCamera, "bench.toml");
  if (state.range(0))
    generate_packets(state, *s.camera);
  else
    generate_all(state, *s.camera);
}
BENCHMARK(BM_BSplineNormal)->ArgName("batch")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// The cameras of three example scenes: a thin-plate surface through nine scattered points with
// normal rays, a dome pulled by two scattered direction samples, a 40 x 30 ray-table lens.
static void example_camera(benchmark::State& state, const char* scene) {
  const Scene s = load_scene(std::filesystem::path(__FILE__).parent_path() / ".." / "examples" /
                             "apps" / scene);
  if (state.range(0))
    generate_packets(state, *s.camera);
  else
    generate_all(state, *s.camera);
}
static void BM_ScatteredNormal(benchmark::State& state) {
  example_camera(state, "scattered_surface.toml");
}
static void BM_ScatteredSphere(benchmark::State& state) {
  example_camera(state, "dome_pulled.toml");
}
static void BM_TableLens(benchmark::State& state) { example_camera(state, "calibrated_lens.toml"); }
BENCHMARK(BM_ScatteredNormal)->ArgName("batch")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ScatteredSphere)->ArgName("batch")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TableLens)->ArgName("batch")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// The same rays in single precision (what a float ray format would cost; the renderer's rays are
// doubles).
struct FloatRayBatch {
  float org[3][kCameraBatch], dir[3][kCameraBatch];
  float dorg_du[3][kCameraBatch], dorg_dv[3][kCameraBatch];
  float ddir_du[3][kCameraBatch], ddir_dv[3][kCameraBatch];
  bool valid[kCameraBatch];
};

// What any camera pays before its own math: a packet kernel that writes the renderer's full ray
// (origin, unit direction and four derivative vectors: 18 doubles per ray, or floats with
// FloatRayBatch) with no camera in it (kNormalize 0: the values are copies of u and v), or that
// also normalizes its direction (one square root and one division per ray, as every camera
// whose directions are not unit does).
template <class T, int kNormalize, class Batch>
[[gnu::always_inline]] inline void floor_kernel(const double* __restrict u,
                                                const double* __restrict v, Batch* __restrict o) {
  // (Values computed from u and v, constants that are no byte pattern: GCC would otherwise turn
  // whole loops into memset and memcpy calls, which is not what a camera kernel does.)
  for (int i = 0; i < kCameraBatch; ++i) {
    T a = T(u[i]) + T(0.5), b = T(v[i]) + T(0.5), c = -1;
    if (kNormalize) {
      const T inv = 1 / std::sqrt(a * a + b * b + 1);
      a *= inv, b *= inv, c *= inv;
    }
    o->org[0][i] = 1, o->org[1][i] = 2, o->org[2][i] = 3;
    o->dir[0][i] = a, o->dir[1][i] = b, o->dir[2][i] = c;
    o->dorg_du[0][i] = 0.5, o->dorg_du[1][i] = 1.5, o->dorg_du[2][i] = 2.5;
    o->dorg_dv[0][i] = 0.5, o->dorg_dv[1][i] = 1.5, o->dorg_dv[2][i] = 2.5;
    o->ddir_du[0][i] = b, o->ddir_du[1][i] = a, o->ddir_du[2][i] = c;
    o->ddir_dv[0][i] = c, o->ddir_dv[1][i] = b, o->ddir_dv[2][i] = a;
  }
  for (int i = 0; i < kCameraBatch; ++i) o->valid[i] = u[i] >= 0;
}
ANAMORPH_KERNEL_BODY void write_rays_body(const double* u, const double* v, CameraRayBatch* o) {
  floor_kernel<double, 0>(u, v, o);
}
constexpr simd::Kernel<write_rays_body> write_rays;
ANAMORPH_KERNEL_BODY void write_normalized_rays_body(const double* u, const double* v,
                                                     CameraRayBatch* o) {
  floor_kernel<double, 1>(u, v, o);
}
constexpr simd::Kernel<write_normalized_rays_body> write_normalized_rays;
ANAMORPH_KERNEL_BODY void write_float_rays_body(const double* u, const double* v,
                                                FloatRayBatch* o) {
  floor_kernel<float, 0>(u, v, o);
}
constexpr simd::Kernel<write_float_rays_body> write_float_rays;

// state.range(0): 0 = writing the rays only, 1 = with one normalization per ray, 2 = writing
// them in single precision.
static void BM_OutputFloor(benchmark::State& state) {
  std::vector<double> us(kW), vs(kH);
  for (int x = 0; x < kW; ++x) us[size_t(x)] = (x + 0.5) / kW;
  for (int y = 0; y < kH; ++y) vs[size_t(y)] = (y + 0.5) / kH;
  CameraSample s[kCameraBatch];
  alignas(64) double u[kCameraBatch], v[kCameraBatch];
  CameraRayBatch out;
  FloatRayBatch out_float;
  for (auto _ : state)
    for (int y = 0; y < kH; y += 4)
      for (int x = 0; x < kW; x += 4) {
        // Handed over as generate_packets and VirtualCamera::generate_batch do.
        for (int k = 0; k < 16; ++k) s[k].uv = {us[size_t(x + (k & 3))], vs[size_t(y + (k >> 2))]};
        split_sample_positions(s, kCameraBatch, u, v);
        if (state.range(0) == 2)
          write_float_rays(u, v, &out_float);
        else if (state.range(0) == 1)
          write_normalized_rays(u, v, &out);
        else
          write_rays(u, v, &out);
        benchmark::DoNotOptimize(&out);
        benchmark::DoNotOptimize(&out_float);
        benchmark::ClobberMemory();
      }
  state.SetItemsProcessed(state.iterations() * kW * kH);
}
BENCHMARK(BM_OutputFloor)
    ->ArgName("variant")
    ->Arg(0)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond);

// The denominator: tracing 1920x1080 primary rays through the bunny, 4x4 packets, one thread.
static void BM_TraceBunny1080p(benchmark::State& state) {
  const std::filesystem::path bunny = std::filesystem::path(__FILE__).parent_path() / ".." / ".." /
                                      "shared" / "scenes" / "ply" / "stanford_bunny" /
                                      "bun_zipper.ply";
  if (!std::filesystem::exists(bunny)) {
    state.SkipWithError("../shared/scenes not found: no bunny to trace");
    return;
  }
  const Scene s = load_scene_from_string(
      "[camera]\nlook_from = [-0.02, 0.11, 0.35]\nlook_at = [-0.02, 0.11, 0.0]\nfov = 40\nfov_axis "
      "= \"vertical\"\n"
      "[[object]]\ntype = \"mesh\"\nfile = \"" +
          bunny.string() + "\"\n",
      "bench.toml", {"image.width=1920", "image.height=1080"});
  const Accel accel(s);
  std::vector<Ray> rays;
  for (int by = 0; by < kH; by += 4)
    for (int bx = 0; bx < kW; bx += 4)
      for (int k = 0; k < 16; ++k) {
        const auto r =
            s.camera->generate({{(bx + (k & 3) + 0.5) / kW, (by + (k >> 2) + 0.5) / kH}});
        rays.push_back(Ray{r->org, r->dir, 0, kInf});
      }
  bool valid[16], found[16];
  std::fill(valid, valid + 16, true);
  Hit hits[16];
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
BENCHMARK(BM_TraceBunny1080p)->Unit(benchmark::kMillisecond);

// What the Python API's Camera.rays(1920, 1080) computes, from C++: the focus+context camera
// (three coins) through generate_ray_field into freshly allocated arrays (origins, directions,
// the four differentials, the mask), on every core. bench/python/rays_vs_cpp runs both.
static void BM_RayField1080p(benchmark::State& state) {
  const std::filesystem::path scene = std::filesystem::path(__FILE__).parent_path() / ".." /
                                      "examples" / "apps" / "focus_context.toml";
  const Scene s = load_scene(scene, {"image.width=1920", "image.height=1080"});
  const size_t n = size_t(kW) * kH;
  for (auto _ : state) {
    std::vector<double> org(3 * n), dir(3 * n), a(3 * n), b(3 * n), c(3 * n), d(3 * n);
    std::vector<uint8_t> valid(n);
    generate_ray_field(
        *s.camera, kW, kH,
        {org.data(), dir.data(), a.data(), b.data(), c.data(), d.data(), valid.data()});
    benchmark::DoNotOptimize(valid.data());
  }
  state.SetItemsProcessed(state.iterations() * int64_t(n));
}
BENCHMARK(BM_RayField1080p)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace anamorph
