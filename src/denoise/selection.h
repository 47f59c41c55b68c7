// NFOR's bandwidth selection (Bitterli et al. 2016, section 5.3): each candidate bandwidth k
// filters both halves; its error is estimated per pixel and channel from the halves themselves,
// the estimates and then the per-pixel choices are smoothed with NL-means, and the halves are
// blended by the smoothed choices.
//
// The estimate: half b is an unbiased estimate of the clean image c, independent of the samples
// of half a, so E[(b - fa)²] = MSE(fa) + Var(b), and
//   MSE(fa) ≈ (b - fa)² - Var(b),   MSE(fb) ≈ (a - fb)² - Var(a),
//   MSE((fa + fb)/2) = (MSE(fa) + MSE(fb))/2 - E[(fa - fb)²]/4
// (the last from ((fa + fb)/2 - c)² = ((fa - c)² + (fb - c)²)/2 - (fa - fb)²/4). It holds for any
// filter, nonlinear weights and the collaborative scheme included; it is approximate only in that
// fa's weights were computed from b (cross-filtering), which couples fa to b's noise through the
// weights.
#pragma once

#include <vector>

#include "denoise/nl_means.h"

namespace anamorph::nfor {

// One bandwidth's result: half a and half b filtered (3 channels each).
struct Candidate {
  Planes a, b;
};

// The estimated MSE of (fa + fb)/2 per channel (3 planes); 0 at uncovered pixels.
void estimate_mse(const Planes& a, const Planes& b, const Planes& var_a, const Planes& var_b,
                  const Candidate& f, const Planes& coverage, Planes& mse);

// Per pixel and channel, 1 for the candidate with the least (smoothed) MSE and 0 for the others
// (the first on a tie); the maps are then smoothed with the filter given, and the candidates
// blended by them into candidates[0] (whose halves hold the result). The MSE planes are freed.
struct Smoother {
  Guide guide;
  PatchKernel kernel;
  int window_radius = 9;
};
void select_and_blend(std::vector<Candidate>& candidates, std::vector<Planes>& mse,
                      const Smoother& smooth, MemoryMeter* meter);

}  // namespace anamorph::nfor
