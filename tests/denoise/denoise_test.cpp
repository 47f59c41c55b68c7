// The denoiser end to end on synthetic half buffers with a known clean image (synthetic.h): how
// far it lowers the error, that a colour affine in the features comes back exactly, that edges
// get no halo, that no-ray pixels take part in nothing, that a partially covered rim does not
// bleed, that noise over constant features averages to the mean, determinism across thread
// counts, the memory estimate, bad input and cancellation.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>

#include "denoise/denoise.h"
#include "math/rng.h"
#include "math/simd.h"
#include "synthetic.h"

namespace anamorph {
namespace {

using test::Synthetic;

// Albedo edges (two halves and a bright disc), a normal discontinuity along the anti-diagonal,
// a depth ramp with a step, and a smooth light variation along x that no feature explains.
Synthetic edges_scene(int w, int h) {
  Synthetic s(w, h);
  const float n1[3] = {0.3f, 0.2f, 1.0f}, n2[3] = {-0.4f, 0.1f, 1.0f};
  const float al[3] = {0.8f, 0.3f, 0.2f}, ar[3] = {0.2f, 0.5f, 0.8f};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const double dx = x - 0.625 * w, dy = y - 0.3 * h;
      const bool spot = dx * dx + dy * dy < 0.025 * w * h;
      for (int c = 0; c < 3; ++c) s.albedo[3 * i + c] = spot ? 0.9f : (x < w / 2 ? al[c] : ar[c]);
      const float* n = x + y < w ? n1 : n2;
      const float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      for (int c = 0; c < 3; ++c) s.normal[3 * i + c] = n[c] / len;
      s.depth[i] = 1.0f + 0.01f * x + (y > 3 * h / 4 ? 0.5f : 0.0f);
    }
  s.shade([&](size_t i, float* rgb) {
    const float l[3] = {0.408f, 0.408f, 0.816f};
    float nl = 0;
    for (int c = 0; c < 3; ++c) nl += s.normal[3 * i + c] * l[c];
    const float x = float(i % size_t(w));
    const float light = (0.2f + 0.8f * std::max(nl, 0.0f)) * (1.0f + 0.2f * std::sin(x / 10.0f));
    for (int c = 0; c < 3; ++c) rgb[c] = s.albedo[3 * i + c] * light;
  });
  return s;
}

std::vector<float> run(const DenoiseInput& in, const DenoiseOptions& o = {},
                       DenoiseStats* stats = nullptr) {
  std::vector<float> out(size_t(in.width) * in.height * 3, -1.0f);
  const DenoiseStats st = denoise(in, o, out.data());
  if (stats) *stats = st;
  return out;
}

// Measured on this scene (48 × 48, noise 0.15 per half): the error falls by 52× with the
// second pass and 51× without; the test asks for 20×, a margin for other seeds and
// compilers.
TEST(Denoise, LowersTheErrorFarBelowTheInput) {
  Synthetic s = edges_scene(48, 48);
  s.add_noise(0.15f, 1);
  const double before = test::mse(s, test::mean_of_halves(s));
  for (bool second : {true, false}) {
    DenoiseOptions o;
    o.second_pass = second;
    const double after = test::mse(s, run(s.input(), o));
    EXPECT_GT(before / after, 20.0)
        << "second pass " << second << ": MSE " << before << " -> " << after;
  }
}

// A first-order fit reproduces any colour that is affine in the regressors (features and pixel
// position), whatever its weights: with no noise in the colour but a stated variance (so the
// weights are broad and reach across every edge), the output is the clean image to float
// rounding, at every covered pixel of a disc with a partial rim. Measured: max error 1.5e-5.
TEST(Denoise, ReproducesAColourAffineInTheFeatures) {
  Synthetic s = edges_scene(40, 40);
  s.cover_disc(20, 20, 17.5);
  s.shade([&](size_t i, float* rgb) {
    const float* al = &s.albedo[3 * i];
    const float* n = &s.normal[3 * i];
    const float x = float(i % 40), y = float(i / 40);
    for (int c = 0; c < 3; ++c)
      rgb[c] = 0.1f + 0.05f * c + 0.6f * al[c] + 0.1f * (al[0] + al[1] + al[2]) +
               (0.2f - 0.1f * c) * n[0] + 0.15f * n[1] - 0.05f * n[2] +
               (0.3f - 0.2f * c) * s.depth[i] + 0.002f * x - 0.001f * y;
  });
  s.add_noise(0.0f, 1);
  const std::vector<float> variance(s.clean.size(), 1e-4f);
  DenoiseInput in = s.input();
  in.variance_a = in.variance_b = variance.data();
  const std::vector<float> out = run(in);
  double worst = 0;
  for (size_t i = 0; i < s.pixels(); ++i)
    for (int c = 0; c < 3; ++c)
      if (s.coverage[i] > 0)
        worst = std::max(worst, std::fabs(double(out[3 * i + c]) - s.clean[3 * i + c]));
  EXPECT_LT(worst, 1e-4);
}

// Mean signed error of channel c of `image` over column x.
double column_bias(const Synthetic& s, const std::vector<float>& image, int x, int c) {
  double sum = 0;
  for (int y = 0; y < s.height; ++y) {
    const size_t i = size_t(y) * s.width + x;
    sum += double(image[3 * i + c]) - s.clean[3 * i + c];
  }
  return sum / s.height;
}

// An albedo edge (x = 16, 32 × 160 pixels) under light that varies along y. Colour leaking
// across would pull the channels beside the edge towards the other side: channel 0 up and
// channel 2 down on the right, the reverse on the left; `leak` is that pull, averaged over three
// columns each side (the step it would erode is 0.72). The windows beside the edge see one side
// only, so their error may grow by their smaller sample, not by a halo. Measured over seeds 1-5:
// leak 0.002-0.004; band MSE 52-91× below the input's and 1.3-3.1× the interior's. The same
// denoise without features (colour weights alone) leaks 0.10 and keeps the band's MSE only 3×
// below the input's: the test would see a halo.
TEST(Denoise, KeepsAlbedoEdgesFreeOfHalos) {
  Synthetic s(32, 160);
  const float al[3] = {0.8f, 0.3f, 0.2f}, ar[3] = {0.2f, 0.5f, 0.8f};
  for (size_t i = 0; i < s.pixels(); ++i)
    for (int c = 0; c < 3; ++c) s.albedo[3 * i + c] = i % 32 < 16 ? al[c] : ar[c];
  s.shade([&](size_t i, float* rgb) {
    const float light = 0.6f + 0.2f * std::sin(float(i / 32) / 12.0f);
    for (int c = 0; c < 3; ++c) rgb[c] = s.albedo[3 * i + c] * light;
  });
  s.add_noise(0.15f, 1);
  const auto band = [](int x, int) { return x >= 13 && x < 19; };
  const auto interior = [](int x, int) { return x < 8 || x >= 24; };
  const auto leak = [&](const std::vector<float>& out) {
    double sum = 0;
    for (int x = 13; x < 19; ++x)
      sum += (x < 16 ? -1 : 1) * (column_bias(s, out, x, 0) - column_bias(s, out, x, 2)) / 6;
    return sum;
  };
  const double before = test::mse(s, test::mean_of_halves(s), band);
  const std::vector<float> out = run(s.input());
  const double after = test::mse(s, out, band), away = test::mse(s, out, interior);
  EXPECT_GT(before / after, 20.0) << "band MSE " << before << " -> " << after;
  EXPECT_LT(after, 5.0 * away) << "band MSE " << after << ", interior " << away;
  EXPECT_LT(std::fabs(leak(out)), 0.02);
  DenoiseInput blind = s.input();
  blind.features.clear();
  EXPECT_GT(leak(run(blind)), 0.05) << "without features the edge should blur";
}

// A piecewise-constant image (0.2 left of x = 16, 0.8 right of it) with Gaussian noise of
// standard deviation 0.1 per half, once as a texture edge (the albedo steps with the colour)
// and once as an edge of the colour alone (a shadow: flat features). The error falls by a stated
// factor, and every pixel beside the edge (columns 15 and 16) keeps its side's value: within
// 0.1 of it (the step is 0.6). Measured (seed 1): texture RMSE 0.0710 -> 0.0109 (6.5x), worst
// beside the edge 0.052; shadow 0.0710 -> 0.0114, worst 0.056. The test asks for 4x and 0.1.
TEST(Denoise, PiecewiseConstantEdgeStaysSharp) {
  for (bool texture : {true, false}) {
    Synthetic s(32, 32);
    s.shade([&](size_t i, float* rgb) {
      for (int c = 0; c < 3; ++c) rgb[c] = i % 32 < 16 ? 0.2f : 0.8f;
    });
    if (texture)
      for (size_t i = 0; i < s.pixels(); ++i)
        for (int c = 0; c < 3; ++c) s.albedo[3 * i + c] = s.clean[3 * i + c];
    s.add_noise(0.1f, 1);
    const double before = std::sqrt(test::mse(s, test::mean_of_halves(s)));
    const std::vector<float> out = run(s.input());
    const double after = std::sqrt(test::mse(s, out));
    double worst = 0;
    for (int y = 0; y < 32; ++y)
      for (int x = 15; x <= 16; ++x)
        for (int c = 0; c < 3; ++c) {
          const size_t i = 3 * (size_t(y) * 32 + x) + c;
          worst = std::max(worst, std::fabs(double(out[i]) - s.clean[i]));
        }
    EXPECT_GT(before / after, 4.0)
        << (texture ? "texture" : "shadow") << ": RMSE " << before << " -> " << after;
    EXPECT_LT(worst, 0.1) << (texture ? "texture" : "shadow") << ": worst error beside the edge";
  }
}

// A textured plane: a disc and a slanted stripe of albedo (edges at every angle and sub-pixel
// position) under light that varies smoothly. Each half's colour is the light times the albedo at
// 8 random points of the pixel (a 16-spp render's half: beside an edge the noise is which side
// its samples fall on), plus Gaussian noise; the albedo feature is the pixel's exact mean (16 × 16
// points: the feature pass's many samples). Demodulated by that albedo, the texture is flat to
// the weights, the edge pixels keep their neighbours across the edge, and the colour comes back
// as the light (smooth) times the exact albedo.
Synthetic textured_plane(int side, std::vector<uint8_t>& edge) {
  Synthetic s(side, side);
  const auto albedo_at = [&](double x, double y, int c) {
    const float disc[3] = {0.2f, 0.5f, 0.8f}, stripe[3] = {0.3f, 0.6f, 0.1f};
    const double dx = x - 0.42 * side, dy = y - 0.45 * side;
    if (dx * dx + dy * dy < 0.06 * side * side) return disc[c];
    if (std::fabs(x - 0.4 * y - 0.62 * side) < 0.09 * side) return stripe[c];
    return 0.8f;
  };
  const auto light = [&](int x, int y) {
    return 0.7f + 0.2f * std::sin(float(x) / 9.0f) * std::cos(float(y) / 13.0f);
  };
  edge.assign(s.pixels(), 0);
  std::vector<float> a(3 * s.pixels()), b(3 * s.pixels());
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      const size_t i = size_t(y) * side + x;
      float first[3] = {albedo_at(x, y, 0), 0, 0}, mean[3] = {0, 0, 0};
      for (int j = 0; j < 256; ++j)
        for (int c = 0; c < 3; ++c) {
          const float v = albedo_at(x + (j % 16 + 0.5) / 16, y + (j / 16 + 0.5) / 16, c);
          mean[c] += v / 256.0f;
          if (c == 0 && v != first[0]) edge[i] = 1;
        }
      Rng rng(i, 7);
      for (std::vector<float>* half : {&a, &b}) {
        float sum[3] = {0, 0, 0};
        for (int k = 0; k < 8; ++k) {
          const double u = rng.uniform(), v = rng.uniform();
          for (int c = 0; c < 3; ++c) sum[c] += albedo_at(x + u, y + v, c) / 8.0f;
        }
        for (int c = 0; c < 3; ++c) (*half)[3 * i + c] = light(x, y) * sum[c];
      }
      for (int c = 0; c < 3; ++c) {
        s.albedo[3 * i + c] = mean[c];
        s.clean[3 * i + c] = light(x, y) * mean[c];
      }
    }
  s.add_noise(0.03f, 5);
  for (size_t i = 0; i < a.size(); ++i) {
    s.a[i] += a[i] - s.clean[i];
    s.b[i] += b[i] - s.clean[i];
  }
  return s;
}

// Measured (48 × 48): RMSE at the edge pixels (those whose albedo mixes two values) 0.0365 in the
// input, 0.0201 denoised without demodulation, 0.0068 with it (MSE 8.9× lower); elsewhere 0.0212,
// 0.0069 and 0.0059. The test asks for 4× at the edges and no loss elsewhere.
TEST(Denoise, DemodulatedTextureEdgesKeepTheirNeighbours) {
  std::vector<uint8_t> edge;
  const Synthetic s = textured_plane(48, edge);
  const auto at_edge = [&](int x, int y) { return edge[size_t(y) * 48 + x] != 0; };
  const auto inside = [&](int x, int y) { return !at_edge(x, y); };
  DenoiseInput in = s.input();
  const std::vector<float> plain = run(in);
  in.demodulation = s.albedo.data();
  const std::vector<float> demodulated = run(in);
  const std::vector<float> noisy = test::mean_of_halves(s);
  for (const auto& [name, keep] : {std::pair{"edge", std::function<bool(int, int)>(at_edge)},
                                   std::pair{"inside", std::function<bool(int, int)>(inside)}})
    std::printf("%s RMSE: input %.5f, plain %.5f, demodulated %.5f\n", name,
                std::sqrt(test::mse(s, noisy, keep)), std::sqrt(test::mse(s, plain, keep)),
                std::sqrt(test::mse(s, demodulated, keep)));
  EXPECT_LT(test::mse(s, demodulated, at_edge), 0.25 * test::mse(s, plain, at_edge));
  EXPECT_LT(test::mse(s, demodulated, inside), test::mse(s, plain, inside));
}

// A fisheye's image circle in a side × side frame: no ray in the corners, a partially covered
// rim (coverage from 16 × 16 points per pixel), the edges scene inside.
Synthetic fisheye_scene(int side, uint64_t seed) {
  Synthetic s = edges_scene(side, side);
  s.cover_disc(0.5 * side, 0.5 * side, 0.46 * side);
  s.add_noise(0.15f, seed);
  return s;
}

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

// Pixels with no ray come out exactly 0, and nothing under them reaches any other pixel: values
// there (colour, features, variance) may be anything, NaN included, without changing one bit.
// (Small windows: the property does not depend on their size, and the test runs four denoises.)
TEST(Denoise, NoRayPixelsStayZeroAndContributeNothing) {
  Synthetic s = fisheye_scene(40, 3);
  const std::vector<float> variance(s.clean.size(), 0.01f);
  DenoiseOptions o;
  o.window_radius = 4;
  o.patch_radius = 2;
  for (bool given : {false, true}) {
    DenoiseInput in = s.input();
    if (given) in.variance_a = in.variance_b = variance.data();
    const std::vector<float> out = run(in, o);
    size_t empty = 0;
    for (size_t i = 0; i < s.pixels(); ++i)
      if (s.coverage[i] == 0) {
        ++empty;
        for (int c = 0; c < 3; ++c) ASSERT_EQ(std::bit_cast<uint32_t>(out[3 * i + c]), 0u) << i;
      }
    ASSERT_GT(empty, 200u);
    Synthetic garbage = s;
    std::vector<float> garbage_variance = variance;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (size_t i = 0; i < s.pixels(); ++i) {
      if (s.coverage[i] != 0) continue;
      for (int c = 0; c < 3; ++c) {
        garbage.a[3 * i + c] = i % 2 ? nan : 1e30f;
        garbage.b[3 * i + c] = i % 3 ? -1e30f : nan;
        garbage.albedo[3 * i + c] = i % 5 ? nan : 7.0f;
        garbage.normal[3 * i + c] = -3.0f;
        garbage_variance[3 * i + c] = i % 2 ? nan : -1.0f;
      }
      garbage.depth[i] = i % 2 ? std::numeric_limits<float>::infinity() : 1e9f;
    }
    DenoiseInput gin = garbage.input();
    if (given) gin.variance_a = gin.variance_b = garbage_variance.data();
    EXPECT_TRUE(same_bits(out, run(gin, o))) << "variance given: " << given;
  }
}

// The rim's pixels (coverage in (0, 1)) hold straight colours of fewer samples: denoised, they
// keep their own colour (no darkening towards the empty corners, no brightening from the
// interior), and their error falls like the rest. Measured: rim MSE 480× below the input's (the
// rim's input is the noisiest: fewer samples), mean signed error +0.004 over its 172 pixels.
TEST(Denoise, PartiallyCoveredRimKeepsItsColour) {
  const Synthetic s = fisheye_scene(48, 4);
  const std::vector<float> out = run(s.input());
  const auto rim = [&](int x, int y) {
    const float c = s.coverage[size_t(y) * s.width + x];
    return c > 0 && c < 1;
  };
  const double before = test::mse(s, test::mean_of_halves(s), rim), after = test::mse(s, out, rim);
  EXPECT_GT(before / after, 10.0) << "rim MSE " << before << " -> " << after;
  double bias = 0;
  int n = 0;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x)
      if (rim(x, y))
        for (int c = 0; c < 3; ++c, ++n) {
          const size_t i = 3 * (size_t(y) * s.width + x) + c;
          bias += out[i] - s.clean[i];
        }
  ASSERT_GT(n, 3 * 100);
  EXPECT_LT(std::fabs(bias / n), 0.01) << "rim mean error over " << n / 3 << " pixels";
}

// The same bits for one thread and two (tiles and sums in a fixed order).
TEST(Denoise, SameBitsForAnyThreadCount) {
  const Synthetic s = fisheye_scene(40, 5);
  std::vector<float> one, two;
  tbb::task_arena(1).execute([&] { one = run(s.input()); });
  tbb::task_arena(2).execute([&] { two = run(s.input()); });
  EXPECT_TRUE(same_bits(one, two));
}

// The bits of the denoised image as one number (FNV-1a over the floats' bit patterns).
uint64_t bits_hash(const std::vector<float>& v) {
  uint64_t h = 1469598103934665603ull;
  for (float f : v) h = (h ^ std::bit_cast<uint32_t>(f)) * 1099511628211ull;
  return h;
}

// Prints the hash of a denoised image, for SameBitsOnEveryInstructionSet (which runs this test
// in a process of its own per set: the kernels' set is chosen once per process).
TEST(Denoise, PrintsTheHashOfItsOutput) {
  const Synthetic s = fisheye_scene(40, 5);
  std::printf("denoise-hash %s %016llx\n", simd::name(simd::active()),
              (unsigned long long)bits_hash(run(s.input())));
}

// The kernels (math/simd.h clones) give the same bits in every instruction set this CPU has.
TEST(Denoise, SameBitsOnEveryInstructionSet) {
  std::string first;
  for (simd::Isa isa : {simd::Isa::Baseline, simd::Isa::Avx2, simd::Isa::Avx512}) {
    if (int(isa) > int(simd::cpu_best())) continue;
    const std::string cmd = std::string("ANAMORPH_ISA=") + simd::name(isa) + " '" +
                            std::filesystem::read_symlink("/proc/self/exe").string() +
                            "' --gtest_filter=Denoise.PrintsTheHashOfItsOutput";
    FILE* p = popen(cmd.c_str(), "r");
    ASSERT_NE(p, nullptr);
    std::string out;
    char buf[256];
    while (std::fgets(buf, sizeof buf, p)) out += buf;
    ASSERT_EQ(pclose(p), 0) << out;
    const size_t at = out.find(std::string("denoise-hash ") + simd::name(isa) + " ");
    ASSERT_NE(at, std::string::npos) << out;
    const std::string hash = out.substr(out.find(' ', at + 13) + 1, 16);
    if (first.empty())
      first = hash;
    else
      EXPECT_EQ(hash, first) << simd::name(isa) << " differs from the baseline";
  }
}

// Noise over constant features and a constant colour: the output converges to the mean. The
// input's mean has a standard error of 0.003 per channel here (the bound is twice that);
// measured: the output's means are -0.0004, +0.0005 and +0.0002 off the truth, its MSE 232×
// below the input's.
TEST(Denoise, UniformNoiseConvergesToTheMean) {
  Synthetic s(48, 48);
  const float truth[3] = {0.5f, 0.3f, 0.2f};
  s.shade([&](size_t, float* rgb) { std::copy_n(truth, 3, rgb); });
  s.add_noise(0.2f, 11);
  const std::vector<float> out = run(s.input());
  const double before = test::mse(s, test::mean_of_halves(s)), after = test::mse(s, out);
  EXPECT_GT(before / after, 100.0) << "MSE " << before << " -> " << after;
  for (int c = 0; c < 3; ++c) {
    double mean = 0;
    for (size_t i = 0; i < s.pixels(); ++i) mean += out[3 * i + c];
    mean /= double(s.pixels());
    EXPECT_NEAR(mean, truth[c], 0.006) << "channel " << c;
  }
}

// The measured peak equals denoise_bytes() on one thread when the variances are given (the
// estimate's assumption; the peak stage is the first pass's fits with the defaults, the choice
// maps' smoothing with four bandwidths and a small window) and stays below it without them and
// on two threads.
TEST(Denoise, MemoryEstimateHoldsThePeak) {
  Synthetic s = edges_scene(40, 40);
  s.add_noise(0.15f, 1);
  const std::vector<float> variance(s.clean.size(), 1e-2f);
  DenoiseOptions small;
  small.window_radius = 2;
  small.bandwidths = {0.3f, 0.6f, 1.0f, 2.0f};
  DenoiseInput in = s.input();
  in.variance_a = in.variance_b = variance.data();
  for (const DenoiseOptions& o : {DenoiseOptions{}, small}) {
    DenoiseStats one;
    tbb::task_arena(1).execute([&] { run(in, o, &one); });
    EXPECT_EQ(one.peak_bytes, denoise_bytes(40, 40, 7, o, 1)) << "radius " << o.window_radius;
  }
  DenoiseStats two, estimated;
  tbb::task_arena(2).execute([&] { run(in, small, &two); });
  EXPECT_LE(two.peak_bytes, denoise_bytes(40, 40, 7, small, 2));
  in.variance_a = in.variance_b = nullptr;
  tbb::task_arena(1).execute([&] { run(in, small, &estimated); });
  EXPECT_LE(estimated.peak_bytes, denoise_bytes(40, 40, 7, small, 1));
}

// Bad input is refused with the field (and pixel) named.
TEST(Denoise, RejectsBadInputNamingIt) {
  Synthetic s = fisheye_scene(64, 6);
  std::vector<float> out(s.clean.size());
  const auto message = [&](const DenoiseInput& in, const DenoiseOptions& o = {}) -> std::string {
    try {
      denoise(in, o, out.data());
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "(accepted)";
  };
  DenoiseInput in = s.input();
  in.width = 0;
  EXPECT_NE(message(in).find("image size 0 x 64"), std::string::npos) << message(in);
  in = s.input();
  in.color_b = nullptr;
  EXPECT_NE(message(in).find("color_a and color_b"), std::string::npos) << message(in);
  in = s.input();
  in.variance_a = s.a.data();
  EXPECT_NE(message(in).find("variance_a and variance_b"), std::string::npos) << message(in);
  Synthetic bad = s;
  bad.a[3 * (10 * 64 + 20) + 1] = std::numeric_limits<float>::quiet_NaN();  // covered
  EXPECT_NE(message(bad.input()).find("color_a at pixel (20, 10) is not finite"), std::string::npos)
      << message(bad.input());
  bad = s;
  bad.coverage[5] = 1.5f;
  EXPECT_NE(message(bad.input()).find("coverage at pixel (5, 0) is 1.5"), std::string::npos)
      << message(bad.input());
  in = s.input();
  in.features.push_back({s.albedo.data(), s.albedo.data(), 3});
  in.features.push_back({s.albedo.data(), s.albedo.data(), 3});
  EXPECT_NE(message(in).find("13 feature channels, at most 12"), std::string::npos) << message(in);
  in = s.input();
  std::vector<float> demodulation(s.clean.size(), 1.0f);
  demodulation[3 * (32 * 64 + 32) + 2] = 0.0f;  // covered
  in.demodulation = demodulation.data();
  EXPECT_NE(message(in).find("demodulation at pixel (32, 32) is 0, not > 0"), std::string::npos)
      << message(in);
  DenoiseOptions o;
  o.window_radius = 17;
  EXPECT_NE(message(s.input(), o).find("window_radius is 17"), std::string::npos);
  o = {};
  o.bandwidths = {0.5f, -1.0f};
  EXPECT_NE(message(s.input(), o).find("bandwidth -1"), std::string::npos);
}

// A cancel flag that is set stops the denoiser between stages and tiles (the flag is read before
// the first tile's work).
TEST(Denoise, StopsWhenCancelled) {
  const Synthetic s = fisheye_scene(40, 7);
  std::atomic<bool> cancel{true};
  DenoiseOptions o;
  o.cancel = &cancel;
  std::vector<float> out(s.clean.size());
  EXPECT_TRUE(denoise(s.input(), o, out.data()).cancelled);
}

}  // namespace
}  // namespace anamorph
