// A feature-guided denoiser for Monte Carlo renderings, in image space: NFOR, "Nonlinearly
// Weighted First-order Regression for Denoising Monte Carlo Renderings" (Bitterli, Rousselle,
// Moon, Iglesias-Guitián, Adler, Mitchell, Jarosz, Novák; EGSR 2016, CGF 35(4)).
//
// The pipeline, and where each step lives:
//  0. Demodulation (optional, DenoiseInput::demodulation; not in the paper, the common practice of
//     production denoisers): the colour divided by a per-pixel factor, typically the albedo, and
//     the result multiplied by it. Beside a texture edge the NL-means weights compare patches
//     that the edge makes unlike, so an edge pixel keeps few neighbours and most of its noise;
//     demodulated, the texture is gone from what the weights compare.
//  1. Variances (variance.h): from the two half buffers, (a - b)²/2 averaged over a 5×5 box,
//     unless the renderer supplies the variance of each half's mean.
//  2. Feature prefiltering (feature_prefilter.h, paper 5.1): every feature channel of every half
//     NL-means filtered with weights from the other half (7×7 patches, 11×11 window, k = 0.5).
//  3. Collaborative first-order regression with cross-filtering (regression.h, paper 5.2): half
//     A's colour is fitted with weights from half B's colour and B's prefiltered features as
//     regressors, and vice versa; 7×7 patches, 19×19 windows, once per bandwidth k (0.5 and 1).
//  4. Selection (selection.h, paper 5.3): per pixel and channel the bandwidth whose estimated
//     MSE (from the other half; smoothed by NL-means, 3×3 patches, 19×19, k = 1) is least; the
//     choice maps smoothed likewise and the halves blended by them.
//  5. Second pass (paper 5.4; on by default): the mean of the two selected halves fitted once
//     more, weights from itself with the variance left between the halves, (a - b)²/4, and the
//     mean of the prefiltered features, refiltered (5×5 window), as regressors, k = 1. Off: the
//     result is the mean of the selected halves.
//
// Where this deviates from the paper (and from Tungsten's public re-implementation), and why:
//  - Coverage (anamorph's cameras have pixels with no ray: outside a fisheye circle, beyond a
//    dome's rim). A pixel with coverage 0 takes part in nothing: no patch distance, weight,
//    regression, variance or MSE reads it, its inputs may hold anything (NaN included), and its
//    output is 0. A partially covered pixel's colour is a straight (un-premultiplied) colour from
//    fewer samples: its weight as a neighbour is scaled by its coverage (∝ its sample count), and
//    the two-buffer variance model divides by it. So the no-ray region neither darkens the rim
//    nor receives colour from it.
//  - A ridge (1e-3 × the sum of the weights) on the slopes of standardized columns (each divided
//    by its weighted standard deviation in the window; the paper scales features to [-1, 1] over
//    the window), and a column constant in the window drops out, instead of an unregularized
//    solve: windows whose features are constant or collinear (a flat wall: depth, normal and
//    position) stay well posed, and a Cholesky solve of the 3 + C normal equations (in double)
//    replaces a QR of the 361-row system. The ridge shrinks a slope by about 0.1%.
//  - Variances of the second pass and of the features are averaged over a small box (the paper
//    uses them per pixel), which keeps one-degree-of-freedom estimates from making the weights
//    spiky. Negative results (a first-order fit overshooting beside a bright edge) become 0.
//  - NL-means distances average the colour channels (as Rousselle et al. 2012 do; Tungsten takes
//    the smallest channel weight); weights are e^-D from a polynomial (relative error 2e-7, so
//    that the loops vectorize) and 0 beyond D = 80.
//  - A tile of a feature channel whose variance is 0 within the filter's reach is copied, not
//    filtered (a noise-free feature has nothing to filter).
//
// Known limit (of any first-order model): where the shading curves across a window that an edge
// cuts to one side, the fit's curvature bias shows beside the edge (tests/denoise: 0.02 at noise
// 0.15 for light varying by ±30% over 56 pixels); it is not colour leaking across the edge.
//
// Determinism: every pass works on tiles fixed by the image size (never by the thread count),
// sums in a fixed order (in lanes of 16, added up in order: the same on every ISA), and the
// regression's overlapping windows scatter in four phases of non-touching tiles (regression.h):
// the output has the same bits for any thread count.
//
// Memory: the denoiser holds whole frames. Beyond its inputs and output, its peak is
// max(13 + 2C + 10K, 7 + 2C + 12K, 21 + 2C, 18 + 3C) floats per pixel for C feature channels and
// K bandwidths (188 bytes at C = 7, K = 2: albedo, normal, depth; 390 MB for 1920 × 1080; 3
// floats less without given variances), plus about 1.6 MB of scratch per thread.
// denoise_bytes() computes it stage by stage, and a test holds the measured peak equal to it.
#pragma once

#include <atomic>
#include <cstddef>
#include <vector>

namespace anamorph {

// One feature, `channels` floats per pixel (interleaved, row-major), for each half.
struct DenoiseFeature {
  const float* a = nullptr;
  const float* b = nullptr;
  int channels = 0;
};

// Two half buffers of one frame: every pixel's samples split in two halves of (nearly) equal
// count, each half averaged on its own. All planes are row-major, width × height pixels,
// channels interleaved; the caller keeps them alive during denoise().
struct DenoiseInput {
  int width = 0, height = 0;
  // Straight (un-premultiplied) RGB of each half: the mean radiance of its covered samples.
  const float* color_a = nullptr;
  const float* color_b = nullptr;
  // Optional RGB variance of each half's mean (sample variance / sample count). Both or neither;
  // without them the variance comes from the difference of the halves (right for
  // low-discrepancy samples, where the sample variance overstates the error of the mean).
  const float* variance_a = nullptr;
  const float* variance_b = nullptr;
  // Coverage (alpha) in [0, 1], one float per pixel: the fraction of the pixel's samples that had
  // a ray. nullptr: every pixel fully covered.
  const float* coverage = nullptr;
  // Optional demodulation, RGB per pixel (> 0 where covered): the colour of both halves (and
  // their variances, by its square) is divided by it before filtering and the result multiplied
  // by it after. Typically the first hit's albedo (1 where the samples miss), from samples
  // enough that its edges are nearly noise-free: a texture edge is then flat in what the weights
  // compare, so the neighbours across it count.
  const float* demodulation = nullptr;
  // Regressors, each averaged over the samples that hit a surface: typically albedo (3), normal
  // (3) and depth (1), optionally the direct light's visibility (1); at most 12 channels in all.
  // Any units and space (depth in scene units, world-space normals), the same in both halves.
  std::vector<DenoiseFeature> features;
};

struct DenoiseOptions {
  int patch_radius = 3;                       // colour NL-means patches: (2f+1)²
  int window_radius = 9;                      // regression windows: (2r+1)², r in [1, 16]
  std::vector<float> bandwidths{0.5f, 1.0f};  // candidate k, one regression pair each
  float ridge = 1e-3f;                        // on the normalized slopes, relative to Σ weights
  bool second_pass = true;                    // paper 5.4 (see above)
  // Read between stages, feature channels and regression tiles; once it is true, denoise()
  // returns soon with cancelled set and the output unspecified.
  const std::atomic<bool>* cancel = nullptr;
};

struct DenoiseStats {
  size_t peak_bytes = 0;  // the most memory the denoiser held at once (its inputs not counted)
  size_t covered_pixels = 0;
  bool cancelled = false;
};

// Denoises the frame into out_rgb (width × height × 3 floats, straight RGB; 0 where coverage is
// 0). Runs on the current TBB task arena. Throws std::invalid_argument naming the field (and
// pixel) for bad input: sizes, missing planes, more than 12 feature channels, coverage outside
// [0, 1], a non-finite value at a covered pixel, options out of range.
DenoiseStats denoise(const DenoiseInput& in, const DenoiseOptions& options, float* out_rgb);

// The peak memory denoise() needs for a frame (for a render's memory estimate), with `threads`
// threads working (each holds its own scratch); the inputs and the output are not included.
size_t denoise_bytes(int width, int height, int feature_channels,
                     const DenoiseOptions& options = {}, int threads = 1);

}  // namespace anamorph
