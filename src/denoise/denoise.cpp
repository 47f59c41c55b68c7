#include "denoise/denoise.h"

#include <algorithm>

#include "denoise/feature_prefilter.h"
#include "denoise/input_checks.h"
#include "denoise/regression.h"
#include "denoise/selection.h"
#include "denoise/variance.h"

namespace anamorph {

using nfor::Candidate;
using nfor::MemoryMeter;
using nfor::Planes;

namespace {

// The colour filters' fixed parameters (the paper's): the MSE and choice maps are smoothed with
// 3×3 patches over the regression's window at k = 1; features are prefiltered with 7×7 patches
// over 11×11 at k = 0.5 and refiltered over 5×5 in the second pass; the second pass regresses
// at k = 1.
constexpr nfor::PatchKernel kSmoothKernel{1, 1.0f};
constexpr nfor::FeatureFilter kPrefilter{{3, 0.5f}, 5};
constexpr nfor::FeatureFilter kRefilter{{3, 0.5f}, 2};
constexpr float kSecondPassK = 1.0f;
const nfor::VarianceEstimate kColorVariance{0.5f, 2, true};

bool cancelled(const DenoiseOptions& o) { return o.cancel && o.cancel->load(); }

// Channels [first, first + channels) of dst from an interleaved plane; 0 at uncovered pixels.
void copy_channels(const float* src, int channels, const Planes& cov, Planes& dst, int first) {
  const size_t n = dst.pixels();
  for (int c = 0; c < channels; ++c) {
    float* o = dst.plane(first + c);
    for (size_t i = 0; i < n; ++i)
      o[i] = cov.plane(0)[i] > 0.0f ? src[i * size_t(channels) + size_t(c)] : 0.0f;
  }
}

// The halves' colours and variances, as the passes read them.
struct Halves {
  Planes a, b, var_a, var_b;  // var_b empty: both halves have var_a
  const Planes& vb() const { return var_b.empty() ? var_a : var_b; }
};

// Divides channels of `p` by in.demodulation (to the power `power`) where covered.
void demodulate(const DenoiseInput& in, const Planes& cov, int power, Planes& p) {
  if (!in.demodulation) return;
  for (int c = 0; c < 3; ++c)
    for (size_t i = 0; i < p.pixels(); ++i) {
      if (!(cov.plane(0)[i] > 0.0f)) continue;
      const float d = in.demodulation[3 * i + size_t(c)];
      p.plane(c)[i] /= power == 2 ? d * d : d;
    }
}

Halves read_colors(const DenoiseInput& in, const Planes& cov, MemoryMeter* meter) {
  const int w = in.width, h = in.height;
  Halves c{Planes(w, h, 3, meter), Planes(w, h, 3, meter), Planes(w, h, 3, meter), Planes()};
  copy_channels(in.color_a, 3, cov, c.a, 0);
  copy_channels(in.color_b, 3, cov, c.b, 0);
  demodulate(in, cov, 1, c.a);
  demodulate(in, cov, 1, c.b);
  if (in.variance_a) {
    c.var_b = Planes(w, h, 3, meter);
    copy_channels(in.variance_a, 3, cov, c.var_a, 0);
    copy_channels(in.variance_b, 3, cov, c.var_b, 0);
    demodulate(in, cov, 2, c.var_a);
    demodulate(in, cov, 2, c.var_b);
  } else {
    nfor::two_buffer_variance(c.a, c.b, cov, kColorVariance, c.var_a, meter);
  }
  return c;
}

// Prefiltered features of both halves (C planes each), one channel at a time (stopping between
// channels when cancelled).
std::pair<Planes, Planes> prefilter_features(const DenoiseInput& in, const Planes& cov,
                                             const DenoiseOptions& o, MemoryMeter* meter) {
  const int w = in.width, h = in.height, channels = nfor::feature_channels(in);
  std::pair<Planes, Planes> out{Planes(w, h, channels, meter), Planes(w, h, channels, meter)};
  int first = 0;
  for (const DenoiseFeature& f : in.features)
    for (int c = 0; c < f.channels; ++c, ++first) {
      if (cancelled(o)) return out;
      Planes ra(w, h, 1, meter), rb(w, h, 1, meter), fa(w, h, 1, meter), fb(w, h, 1, meter);
      for (size_t i = 0; i < ra.pixels(); ++i) {
        const bool covered = cov.plane(0)[i] > 0.0f;
        ra.plane(0)[i] = covered ? f.a[i * size_t(f.channels) + size_t(c)] : 0.0f;
        rb.plane(0)[i] = covered ? f.b[i * size_t(f.channels) + size_t(c)] : 0.0f;
      }
      nfor::prefilter_channel(ra, rb, cov, kPrefilter, fa, fb, meter);
      std::copy_n(fa.plane(0), fa.pixels(), out.first.plane(first));
      std::copy_n(fb.plane(0), fb.pixels(), out.second.plane(first));
    }
  return out;
}

// Both halves cross-filtered at every bandwidth (A fitted with B's weights and features, and vice
// versa), and the MSE estimates of their means.
std::vector<Candidate> filter_halves(const Halves& c, const std::pair<Planes, Planes>& features,
                                     const Planes& cov, const DenoiseOptions& o,
                                     std::vector<Planes>& mse, MemoryMeter* meter) {
  const int w = c.a.width(), h = c.a.height();
  std::vector<Candidate> f;
  std::vector<Planes*> out_a, out_b;
  for (size_t k = 0; k < o.bandwidths.size(); ++k)
    f.push_back({Planes(w, h, 3, meter), Planes(w, h, 3, meter)});
  for (Candidate& fk : f) {
    out_a.push_back(&fk.a);
    out_b.push_back(&fk.b);
  }
  nfor::RegressionInput r;
  r.window_radius = o.window_radius;
  r.patch_radius = o.patch_radius;
  r.bandwidths = o.bandwidths;
  r.ridge = o.ridge;
  r.color = &c.a;
  r.guide = {&c.b, &c.vb(), &cov};
  r.features = &features.second;
  nfor::collaborative_regression(r, out_a, meter, o.cancel);
  r.color = &c.b;
  r.guide = {&c.a, &c.var_a, &cov};
  r.features = &features.first;
  nfor::collaborative_regression(r, out_b, meter, o.cancel);
  for (const Candidate& fk : f) {
    mse.emplace_back(w, h, 3, meter);
    nfor::estimate_mse(c.a, c.b, c.var_a, c.vb(), fk, cov, mse.back());
  }
  return f;
}

// The guide of the MSE and choice smoothing: the mean of the halves and its variance, written
// over half A's planes (the halves are not needed after the regressions).
void make_mean_guide(Halves& c) {
  const Planes& vb = c.vb();
  for (int ch = 0; ch < 3; ++ch)
    for (size_t i = 0; i < c.a.pixels(); ++i) {
      c.a.plane(ch)[i] = 0.5f * (c.a.plane(ch)[i] + c.b.plane(ch)[i]);
      c.var_a.plane(ch)[i] = 0.25f * (c.var_a.plane(ch)[i] + vb.plane(ch)[i]);
    }
  c.b.release();
  c.var_b.release();
}

// Paper 5.4: the mean of the selected halves regressed once more on refiltered features.
void second_pass(Candidate& r, std::pair<Planes, Planes>& features, const Planes& cov,
                 const DenoiseOptions& o, Planes& out, MemoryMeter* meter) {
  const int w = cov.width(), h = cov.height();
  Planes final_features(w, h, features.first.channels(), meter);
  nfor::refilter_features(features.first, features.second, cov, kRefilter, final_features, meter);
  features.first.release();
  features.second.release();
  Planes var(w, h, 3, meter);
  nfor::two_buffer_variance(r.a, r.b, cov, {0.25f, 1, false}, var, meter);
  for (int c = 0; c < 3; ++c)
    for (size_t i = 0; i < r.a.pixels(); ++i)
      r.a.plane(c)[i] = 0.5f * (r.a.plane(c)[i] + r.b.plane(c)[i]);
  r.b.release();
  nfor::RegressionInput in;
  in.color = &r.a;
  in.guide = {&r.a, &var, &cov};
  in.features = &final_features;
  in.window_radius = o.window_radius;
  in.patch_radius = o.patch_radius;
  in.bandwidths = {kSecondPassK};
  in.ridge = o.ridge;
  Planes* outs[] = {&out};
  nfor::collaborative_regression(in, outs, meter, o.cancel);
}

// Interleaved straight RGB (modulated again): 0 where uncovered, negative values clamped to 0.
void write_output(const DenoiseInput& in, const Planes& result, const Planes& cov, float* out_rgb) {
  const size_t n = result.pixels();
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) {
      const size_t o = 3 * i + size_t(c);
      const float d = in.demodulation ? in.demodulation[o] : 1.0f;
      out_rgb[o] = cov.plane(0)[i] > 0.0f ? std::max(result.plane(c)[i] * d, 0.0f) : 0.0f;
    }
}

}  // namespace

DenoiseStats denoise(const DenoiseInput& in, const DenoiseOptions& o, float* out_rgb) {
  nfor::check_input(in, o, out_rgb);
  MemoryMeter meter;
  DenoiseStats stats;
  const int w = in.width, h = in.height;
  Planes cov(w, h, 1, &meter);
  for (size_t i = 0; i < cov.pixels(); ++i) {
    cov.plane(0)[i] = in.coverage ? in.coverage[i] : 1.0f;
    stats.covered_pixels += cov.plane(0)[i] > 0.0f;
  }
  const auto stop = [&] {
    stats.peak_bytes = meter.peak();
    stats.cancelled = true;
    return stats;
  };
  Halves colors = read_colors(in, cov, &meter);
  auto features = prefilter_features(in, cov, o, &meter);
  if (cancelled(o)) return stop();
  std::vector<Planes> mse;
  std::vector<Candidate> candidates = filter_halves(colors, features, cov, o, mse, &meter);
  if (cancelled(o)) return stop();
  make_mean_guide(colors);
  nfor::select_and_blend(
      candidates, mse, {{&colors.a, &colors.var_a, &cov}, kSmoothKernel, o.window_radius}, &meter);
  colors = Halves{};
  if (cancelled(o)) return stop();
  Candidate& r = candidates[0];
  Planes result(w, h, 3, &meter);
  if (o.second_pass) {
    second_pass(r, features, cov, o, result, &meter);
  } else {
    for (int c = 0; c < 3; ++c)
      for (size_t i = 0; i < result.pixels(); ++i)
        result.plane(c)[i] = 0.5f * (r.a.plane(c)[i] + r.b.plane(c)[i]);
  }
  if (cancelled(o)) return stop();
  write_output(in, result, cov, out_rgb);
  stats.peak_bytes = meter.peak();
  return stats;
}

size_t denoise_bytes(int width, int height, int feature_channels, const DenoiseOptions& o,
                     int threads) {
  // The stages of denoise() as (floats per pixel held, one thread's scratch), with the variances
  // given (without them the first stages hold 3 floats per pixel less).
  const size_t c = size_t(std::max(feature_channels, 0)), k = o.bandwidths.size();
  const int f = o.patch_radius, r = o.window_radius;
  const size_t filter1 =
      nfor::nl_means_scratch_bytes(kPrefilter.window_radius, kPrefilter.kernel.patch_radius, 1);
  const size_t refilter1 =
      nfor::nl_means_scratch_bytes(kRefilter.window_radius, kRefilter.kernel.patch_radius, 1);
  const size_t regression = nfor::regression_scratch_bytes(r, f, int(c));
  const size_t smooth = nfor::nl_means_scratch_bytes(r, kSmoothKernel.patch_radius, 3 * int(k));
  const size_t inputs = 1 + 6 + 6;  // coverage, the halves' colours and variances
  std::vector<std::pair<size_t, size_t>> stages = {
      {inputs + 2 * c + 4 + 1 + 3, 0},        // a feature channel's variance (prefilter_features)
      {inputs + 2 * c + 4 + 1, filter1},      // and its NL-means
      {inputs + 2 * c + 10 * k, regression},  // the first pass's fits (filter_halves)
  };
  if (k >= 2) stages.push_back({7 + 2 * c + 12 * k, smooth});  // select_and_blend
  if (o.second_pass) {
    stages.push_back({18 + 3 * c, 0});          // refilter_features: a channel's residual variance
    stages.push_back({15 + 3 * c, refilter1});  // and its NL-means
    stages.push_back({14 + c, regression});     // the last fit
  } else {
    stages.push_back({10 + 2 * c, 0});
  }
  const size_t pixels = size_t(width) * size_t(height);
  size_t most = 0;
  for (const auto& [floats, scratch] : stages)
    most = std::max(most, floats * sizeof(float) * pixels + size_t(std::max(threads, 0)) * scratch);
  return most;
}

}  // namespace anamorph
