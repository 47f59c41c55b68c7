// NFOR's collaborative first-order regression (Bitterli et al. 2016, section 5.2 of the paper):
// around every pixel c, a weighted least-squares fit of the colour as an affine function
// of the pixel offset and the feature values in a (2R+1)² window,
//
//   min over beta  sum_j w(c, j) (y_j - beta · x_j)²  + ridge · sum_j w(c, j) · |beta_slopes|²,
//   x_j = (1, (j - c)/R, f_1(j) - f_1(c), ..., f_C(j) - f_C(c)),
//
// with NL-means weights w (nl_means.h) computed from the colour alone (the paper's finding:
// feature-based weights help zero-order filters but hurt first-order ones). The ridge acts on
// standardized columns (each divided by its w-weighted standard deviation in the window; a column
// constant there drops out): the paper normalizes each feature to [-1, 1] over the window, and
// either way the scale matters only for how the ridge treats the columns. With the columns
// standardized, the ridge shrinks the slopes by about the fraction `ridge`. The fit then predicts
// every pixel of the window, not only c, and a pixel's output is the w-weighted mean of the
// predictions of all windows that contain it (the collaborative scheme).
//
// Determinism: windows scatter into the frame. Tiles are processed in four phases by the parity
// of their column and row; within a phase no two tiles reach the same pixel (tiles.h), and within
// a tile the centres go in row-major order, so every pixel's sum has one order for any thread
// count.
#pragma once

#include <atomic>
#include <span>
#include <vector>

#include "denoise/nl_means.h"

namespace anamorph::nfor {

struct RegressionInput {
  const Planes* color = nullptr;     // the values fitted: 3 channels
  Guide guide;                       // the weights (the other half's colour, when cross-filtering)
  const Planes* features = nullptr;  // the regressors: up to kMaxFeatureChannels channels
  int window_radius = 9;
  int patch_radius = 3;
  std::vector<float> bandwidths{1.0f};  // one fit per k, sharing the patch distances
  float ridge = 1e-3f;
};

// out[k] (3 channels each): the result at bandwidths[k]; 0 at uncovered pixels. Returns early
// (out incomplete) when *cancel turns true.
void collaborative_regression(const RegressionInput& in, std::span<Planes* const> out,
                              MemoryMeter* meter, const std::atomic<bool>* cancel);

// Bytes one thread's scratch takes (the whole-frame accumulator is counted by the caller: 4
// floats per pixel).
size_t regression_scratch_bytes(int window_radius, int patch_radius, int features);

}  // namespace anamorph::nfor
