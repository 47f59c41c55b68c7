// A render denoised (`render --denoise`, docs/denoise.md): the frame rendered in two halves of
// its samples, [0, spp/2) and [spp/2, spp), each kept in a film of its own with the features the
// denoiser regresses on (albedo, normal, depth and the fraction of the covered samples that hit
// a surface), NFOR (denoise/denoise.h) run over the whole frame, and the halves merged into one
// film whose beauty is the denoised colour: the outputs then resolve it as any film (the AOV
// layers and sample counts are those of the undenoised render; alpha too, except at a rim,
// where it is computed from the camera: denoise_halves).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "denoise/denoise.h"
#include "render/renderer.h"

namespace anamorph {

// `aovs` with the layers the denoiser needs (albedo, normal, depth) added at the end when absent.
std::vector<Aov> with_denoise_aovs(std::vector<Aov> aovs);

// Why these settings cannot be denoised ("needs uniform sampling ..."), or none.
std::optional<std::string> denoise_unsupported(const RenderSettings& rs);

// The samples per pixel of the features (albedo, normal, depth, hit fraction) a render of `spp`
// samples is denoised with: more than the colour's (8 times, at most 256, never fewer than
// spp). They are rendered apart, in the albedo view (first hits only, no light paths: cheap),
// split in halves as the colour is, so that a pixel's share of each side of a texture or
// geometry edge is nearer the truth in the regressors than in its 16-sample colour.
uint32_t denoise_feature_spp(int spp);

// What denoising a width x height frame holds besides the film it renders into: the other
// half's film, the denoiser's input planes and its peak (denoise_bytes), with `threads` threads.
uint64_t denoise_film_bytes(int width, int height, size_t film_aov_floats, int threads);

struct DenoisedRender {
  RenderStats stats;
  DenoiseStats denoise;
  double denoise_seconds = 0;
  bool denoised = false;  // false when the render was cancelled or stopped by its time limit
};

// Renders into `film` (whose AOVs must include with_denoise_aovs' layers: std::invalid_argument
// otherwise) in two halves and denoises its beauty. `rs` are the renderer's scene's settings
// (denoise_unsupported must accept them); its features are rendered in a pass of their own
// (denoise_feature_spp), counted in denoise_seconds. Cancelled or out of time: the film holds
// every sample taken, not denoised.
DenoisedRender render_denoised(const Renderer& renderer, const RenderSettings& rs, Film& film,
                               RenderOptions opt, const DenoiseOptions& options = {});

// The denoising step alone: half `a`'s samples merged into `film` (which holds half b), and the
// merged film's beauty replaced by NFOR's estimate from the two halves. Every pixel without a
// ray in either half keeps its (transparent) value. With `scene` (whose camera and settings
// rendered the film) and rim_coverage_applies: every pixel beside the no-ray boundary that has
// a sample with a ray takes its coverage (alpha) from the camera (render/rim_coverage.h).
// With `features_a` and `features_b` (films of with_denoise_aovs({}) layers, the same size), the
// features come from them instead of from `a` and `film`.
DenoiseStats denoise_halves(Film& a, Film& film, const DenoiseOptions& options = {},
                            const Scene* scene = nullptr, const Film* features_a = nullptr,
                            const Film* features_b = nullptr);

}  // namespace anamorph
