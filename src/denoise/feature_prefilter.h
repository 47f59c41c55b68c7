// NFOR's feature prefiltering (Bitterli et al. 2016, section 5.1, after Rousselle et al. 2013):
// features are noisy wherever a pixel's samples see different surfaces (edges, depth of field,
// motion blur, glossy albedo), and a regression on noisy regressors is biased. Each channel of
// each half is filtered with NL-means whose weights come from the other half (cross-filtering:
// the weights are independent of the values they average), with the channel's two-buffer
// variance. Where a channel is noise-free (variance 0 over a tile's reach) it passes unchanged.
#pragma once

#include "denoise/nl_means.h"

namespace anamorph::nfor {

struct FeatureFilter {
  PatchKernel kernel{3, 0.5f};
  int window_radius = 5;
};

// One channel: raw halves a and b (1 plane each) filtered into out_a and out_b.
void prefilter_channel(const Planes& a, const Planes& b, const Planes& coverage,
                       const FeatureFilter& filter, Planes& out_a, Planes& out_b,
                       MemoryMeter* meter);

// The second pass's features (section 5.4): the mean of the prefiltered halves, filtered once
// more with the variance left between them, (a - b)²/4.
void refilter_features(const Planes& a, const Planes& b, const Planes& coverage,
                       const FeatureFilter& filter, Planes& out, MemoryMeter* meter);

}  // namespace anamorph::nfor
