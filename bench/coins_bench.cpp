// Ray generation with centers of interest: 1920x1080 rays (one per pixel center) without coins,
// with 1000 small coins spread over the image (a jittered grid of image positions), and
// with one large coin (radius 0.3 around the first grid position). The per-sample cost depends only
// on the coins that reach the sample (a uniform grid over (u, v)), so 1000 small coins must cost
// less than 2x no coin.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>

#include "camera/presets.h"
#include "math/rng.h"

namespace anamorph {

namespace {

constexpr int kW = 1920, kH = 1080;

VirtualCameraParts parts(const std::string& preset) {
  const std::string rig = "look_from = [0, 0, 0]\nlook_at = [0, 0, -1]\nup = [0, 1, 0]\n";
  if (preset == "fisheye") return make_preset("fisheye", rig + "fov = 180", {kW, kH});
  return make_preset("perspective", rig + "fov = 60", {kW, kH});
}

// n coins at distance 5 along the undistorted rays of a jittered grid of image positions (cells
// with no ray, e.g. outside a fisheye's circle, draw again until n coins are placed).
std::vector<Coin> spread_coins(const VirtualCamera& plain, int n, double radius) {
  Rng rng(1, 2);
  std::vector<Coin> coins;
  const int nu = int(std::ceil(std::sqrt(n * 16.0 / 9))), nv = (n + nu - 1) / nu;
  for (int k = 0; int(coins.size()) < n && k < 100 * n; ++k) {
    const int i = k % nu, j = (k / nu) % nv;
    const Vec2 uv{(i + 0.2 + 0.6 * rng.uniform()) / nu, (j + 0.2 + 0.6 * rng.uniform()) / nv};
    const auto r = plain.generate({uv});
    if (!r) continue;
    Coin c;
    c.position = r->org + r->dir * 5.0;
    c.strength = 0.4;
    c.radius = radius;
    coins.push_back(c);
  }
  return coins;
}

void generate_all(benchmark::State& state, const VirtualCamera& cam) {
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

// range(0): 0 = no coin, 1 = 1000 coins of radius 0.01, 2 = 1000 of radius 0.005,
// 3 = one coin of radius 0.3.
void BM_CoinRays(benchmark::State& state, const std::string& preset) {
  const VirtualCamera plain(parts(preset));
  VirtualCameraParts p = parts(preset);
  switch (state.range(0)) {
    case 1:
      p.coins = spread_coins(plain, 1000, 0.01);
      break;
    case 2:
      p.coins = spread_coins(plain, 1000, 0.005);
      break;
    case 3:
      p.coins = spread_coins(plain, 1, 0.3);
      break;
    default:
      break;
  }
  const VirtualCamera cam(std::move(p));
  // Share of the image that some coin reaches.
  int reached = 0;
  for (int y = 0; y < kH; y += 4)
    for (int x = 0; x < kW; x += 4)
      reached += cam.coins().reaches({(x + 0.5) / kW, (y + 0.5) / kH});
  state.counters["coins"] = double(cam.coins().sites().size());
  state.counters["reached"] = reached / double((kW / 4) * (kH / 4));
  generate_all(state, cam);
}

// On a shared machine the fastest repetition is the least disturbed one: run with
// --benchmark_repetitions=N --benchmark_enable_random_interleaving=true and compare the "min"
// rows.
double fastest(const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); }

BENCHMARK_CAPTURE(BM_CoinRays, perspective, std::string("perspective"))
    ->DenseRange(0, 3)
    ->ComputeStatistics("min", fastest)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_CoinRays, fisheye, std::string("fisheye"))
    ->DenseRange(0, 3)
    ->ComputeStatistics("min", fastest)
    ->Unit(benchmark::kMillisecond);

}  // namespace

}  // namespace anamorph
