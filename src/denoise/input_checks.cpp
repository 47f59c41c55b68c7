#include "denoise/input_checks.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include "denoise/least_squares.h"

namespace anamorph::nfor {

namespace {

[[noreturn]] void fail(const std::string& what) { throw std::invalid_argument("denoise: " + what); }

std::string pixel(size_t i, int width) {
  std::ostringstream s;
  s << "(" << i % size_t(width) << ", " << i / size_t(width) << ")";
  return s.str();
}

// A value as the message shows it ("nan", "inf", "-0.5").
std::string text(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// Every value of a covered pixel finite.
void check_finite(const float* plane, int channels, const float* coverage, const DenoiseInput& in,
                  const std::string& name) {
  const size_t n = size_t(in.width) * size_t(in.height);
  for (size_t i = 0; i < n; ++i) {
    if (coverage && !(coverage[i] > 0.0f)) continue;
    for (int c = 0; c < channels; ++c)
      if (!std::isfinite(plane[i * channels + c]))
        fail(name + " at pixel " + pixel(i, in.width) + " is not finite (" +
             text(plane[i * channels + c]) + ")");
  }
}

void check_planes(const DenoiseInput& in) {
  if (!in.color_a || !in.color_b) fail("color_a and color_b are required");
  if (bool(in.variance_a) != bool(in.variance_b))
    fail("variance_a and variance_b go together (give both or neither)");
  const size_t n = size_t(in.width) * size_t(in.height);
  if (in.coverage)
    for (size_t i = 0; i < n; ++i)
      if (!(in.coverage[i] >= 0.0f && in.coverage[i] <= 1.0f))
        fail("coverage at pixel " + pixel(i, in.width) + " is " + text(in.coverage[i]) +
             ", not in [0, 1]");
  check_finite(in.color_a, 3, in.coverage, in, "color_a");
  check_finite(in.color_b, 3, in.coverage, in, "color_b");
  if (in.demodulation) {
    check_finite(in.demodulation, 3, in.coverage, in, "demodulation");
    const size_t n3 = 3 * n;
    for (size_t i = 0; i < n3; ++i)
      if (!(in.coverage && !(in.coverage[i / 3] > 0.0f)) && !(in.demodulation[i] > 0.0f))
        fail("demodulation at pixel " + pixel(i / 3, in.width) + " is " + text(in.demodulation[i]) +
             ", not > 0");
  }
  if (in.variance_a) {
    check_finite(in.variance_a, 3, in.coverage, in, "variance_a");
    check_finite(in.variance_b, 3, in.coverage, in, "variance_b");
  }
  for (size_t f = 0; f < in.features.size(); ++f) {
    const DenoiseFeature& feature = in.features[f];
    const std::string name = "features[" + std::to_string(f) + "]";
    if (!feature.a || !feature.b) fail(name + ": both halves (a and b) are required");
    if (feature.channels < 1) fail(name + ": channels is " + std::to_string(feature.channels));
    check_finite(feature.a, feature.channels, in.coverage, in, name + ".a");
    check_finite(feature.b, feature.channels, in.coverage, in, name + ".b");
  }
}

void check_options(const DenoiseOptions& o) {
  if (o.patch_radius < 0 || o.patch_radius > 8)
    fail("patch_radius is " + std::to_string(o.patch_radius) + ", not in [0, 8]");
  if (o.window_radius < 1 || o.window_radius > 16)
    fail("window_radius is " + std::to_string(o.window_radius) + ", not in [1, 16]");
  if (o.bandwidths.empty()) fail("bandwidths is empty (give at least one k)");
  for (float k : o.bandwidths)
    if (!(k > 0.0f && std::isfinite(k))) fail("bandwidth " + text(k) + " is not a positive number");
  if (!(o.ridge >= 0.0f && std::isfinite(o.ridge)))
    fail("ridge is " + text(o.ridge) + ", not a number >= 0");
}

}  // namespace

int feature_channels(const DenoiseInput& in) {
  long total = 0;
  for (const DenoiseFeature& f : in.features) total += std::max(f.channels, 0);
  return int(std::min<long>(total, std::numeric_limits<int>::max()));
}

void check_input(const DenoiseInput& in, const DenoiseOptions& options, const float* out_rgb) {
  if (in.width < 1 || in.height < 1)
    fail("image size " + std::to_string(in.width) + " x " + std::to_string(in.height) +
         " has no pixels");
  if (!out_rgb) fail("out_rgb is null");
  check_options(options);
  if (feature_channels(in) > kMaxFeatureChannels)
    fail(std::to_string(feature_channels(in)) + " feature channels, at most " +
         std::to_string(kMaxFeatureChannels));
  check_planes(in);
}

}  // namespace anamorph::nfor
