// What denoise() accepts: sizes, planes, feature channel counts, coverage and finite values at
// covered pixels, options in range. Each failure names the field (and the pixel).
#pragma once

#include "denoise/denoise.h"

namespace anamorph::nfor {

// Throws std::invalid_argument ("denoise: ...") for the first problem found.
void check_input(const DenoiseInput& in, const DenoiseOptions& options, const float* out_rgb);

// The feature channels of all features together.
int feature_channels(const DenoiseInput& in);

}  // namespace anamorph::nfor
