// Non-local means weights and the pixel-wise NL-means filter (Buades et al. 2005), in the form
// Rousselle, Knaus and Zwicker use for Monte Carlo renderings ("Adaptive rendering with non-local
// means filtering", 2012): the squared difference of two pixels has the variance it expects from
// noise subtracted and is divided by the variance times k², so the bandwidth k is in units of the
// noise and a pixel's own noise does not make it look unlike its neighbours.
//
//   d_c(p, q) = ((u_c(p) - u_c(q))² - (Var_c(p) + min(Var_c(p), Var_c(q))))
//               / (k² (eps + Var_c(p) + Var_c(q)))
//   D(p, q)   = mean over the channels c and the (2f+1)² patch offsets n of d_c(p + n, q + n)
//   w(p, q)   = exp(-max(0, D(p, q))) · coverage(q)
//
// (with eps inside the variance sum, D at bandwidth k is D at k = 1 over k², so several
// bandwidths share one distance computation).
//
// Image space and any camera: a pixel with no ray (coverage 0) and a pixel outside the image are
// left out of every patch mean (the mean is over the pairs present) and get weight 0; a partially
// covered pixel's weight is scaled by its coverage, which is proportional to its sample count,
// i.e. to the inverse of its straight colour's variance.
#pragma once

#include <span>

#include "denoise/planes.h"
#include "denoise/tiles.h"

namespace anamorph::nfor {

// What the weights are computed from: the guide's values (1 or 3 channels: a feature channel
// or a colour), the variance of each value, and each pixel's coverage (alpha; 0 = no ray).
struct Guide {
  const Planes* value = nullptr;
  const Planes* variance = nullptr;
  const Planes* coverage = nullptr;
};

// Throws std::invalid_argument unless the guide has 1 or 3 channels and its planes match.
void check_guide(const Guide& g);

struct PatchKernel {
  int patch_radius = 3;  // f: patches of (2f+1)² pixels
  float k = 0.5f;        // bandwidth, in units of the noise's standard deviation
};

// Per-thread buffers for patch_distances over rectangles of up to `side` × `side` pixels.
class PatchScratch {
 public:
  PatchScratch(int side, int patch_radius, MemoryMeter* meter);
  static size_t bytes(int side, int patch_radius);
  float* dist() { return dist_.data(); }
  float* count() { return count_.data(); }
  float* row_dist() { return row_dist_.data(); }
  float* row_count() { return row_count_.data(); }

 private:
  MeteredFloats dist_, count_, row_dist_, row_count_;
};

// D(p, p + (dx, dy)) at k = 1 for every pixel p of r, row-major into out[r.area()]; the
// distance at bandwidth k is D / k² (eps sits inside the variance sum). Where p or its neighbour
// is outside the image or uncovered the value is meaningless: callers give such pairs weight 0.
void patch_distances(const Guide& g, int patch_radius, const Rect& r, int dx, int dy,
                     PatchScratch& scratch, float* out);

// w = exp(-max(D / k², 0)) · coverage(q) for n pairs, 0 where D / k² >= 80 (distance and out
// may be one array).
void weights_from_distances(int n, const float* distance, float k, const float* coverage,
                            float* out);

// Pixel-wise NL-means over a window of radius window_radius: each output pixel is the weighted
// mean of its window, with one weight per pixel pair (from the guide) for every channel of every
// input. in[i] and out[i] have the same channel count; uncovered pixels come out 0. With
// copy_noise_free, a tile whose guide has variance 0 everywhere within its reach (window and
// patch) is copied from the input: a noise-free feature has nothing to filter.
void nl_means(const Guide& g, const PatchKernel& kernel, int window_radius,
              std::span<const Planes* const> in, std::span<Planes* const> out, MemoryMeter* meter,
              bool copy_noise_free = false);

// The bytes nl_means holds per thread (its scratch) beyond its outputs.
size_t nl_means_scratch_bytes(int window_radius, int patch_radius, int channels);

}  // namespace anamorph::nfor
