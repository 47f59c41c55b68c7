// Per-pixel variance from two half buffers of independent samples. The difference of the halves
// has twice a half's variance, so (a - b)²/2 estimates Var(a) with one degree of freedom; the
// estimate is averaged over a box of covered pixels. It is the estimate NFOR's authors use for
// low-discrepancy samples, where a per-sample variance overstates the error of the mean (anamorph
// draws its paths from Owen-scrambled Sobol' points).
#pragma once

#include "denoise/planes.h"

namespace anamorph::nfor {

struct VarianceEstimate {
  // Var of what: 0.5 for either half ((a - b)²/2), 0.25 for their mean ((a - b)²/4).
  float scale = 0.5f;
  int radius = 2;  // box of (2r+1)² pixels
  // The values are straight colours whose variance scales with 1/coverage (a pixel covered by a
  // fraction α of its samples): the box averages α·scale·(a - b)² and divides by the centre's α.
  bool by_coverage = true;
};

// out (a.channels() planes) = the variance estimate per channel; 0 at uncovered pixels.
void two_buffer_variance(const Planes& a, const Planes& b, const Planes& coverage,
                         const VarianceEstimate& how, Planes& out, MemoryMeter* meter);

}  // namespace anamorph::nfor
