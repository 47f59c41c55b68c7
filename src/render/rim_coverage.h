// The coverage of the pixels beside a camera's no-ray boundary (a fisheye's image circle, a
// dome's rim), computed from the camera alone: the fraction of the pixel's sample positions at
// which the camera has a ray, over g × g stratified positions warped as the renderer warps its
// samples (render/sampler.h). No ray is traced. The denoiser (render/denoise_film.h) sets a rim
// pixel's alpha from it instead of from the pixel's few samples: coverage is a property of the
// camera, and its sample noise is most of what is left at a denoised dome's rim.
#pragma once

#include <cstdint>
#include <vector>

#include "scene/scene.h"

namespace anamorph {

// Whether rim_coverage() gives the expected alpha of a render with these settings: the samples
// spread over the pixel (not the `center` sampler, whose alpha is already exact) and the camera's
// rays do not depend on lens or time samples.
bool rim_coverage_applies(const Camera& cam, const RenderSettings& rs);

// Per pixel of a width × height image (row-major): the coverage where `pixels` is non-zero, -1
// elsewhere. The same bits for any thread count (each pixel on its own).
std::vector<float> rim_coverage(const Camera& cam, const RenderSettings& rs, int width, int height,
                                const std::vector<uint8_t>& pixels, int grid = 32);

}  // namespace anamorph
