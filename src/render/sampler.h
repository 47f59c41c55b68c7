// Pixel sample positions. `center`: exactly the pixel center. `stratified`: the renderer's
// sample passes take positions and every later number (lens, time, each bounce's light, BSDF and
// roulette numbers) from the pixel's Owen-scrambled Sobol' points (Rng::qmc), so every prefix of
// a pixel's samples is stratified. `random`: independent uniform. The Gaussian filter warps the
// position by filter importance sampling, so every sample has weight 1 and no sample crosses into
// another pixel's sums.
#pragma once

#include <cmath>
#include <string>

#include "math/rng.h"
#include "math/vec.h"
#include "scene/scene.h"

namespace anamorph {

// Offset of a sample inside the pixel, in [0,1)^2 (before filter warping), for the samplers
// without a QMC stream.
inline Vec2 pixel_offset(SamplerKind k, Rng& rng) {
  if (k == SamplerKind::Center) return {0.5, 0.5};
  const double a = rng.uniform();
  return {a, rng.uniform()};
}

// Truncated radial Gaussian (sigma = radius / 3) by inverse CDF: offset from the pixel center.
inline Vec2 gaussian_offset(Vec2 u, double radius) {
  const double sigma = radius / 3;
  const double tail = 1 - std::exp(-radius * radius / (2 * sigma * sigma));
  const double r = sigma * std::sqrt(-2 * std::log(1 - u.x * tail));
  const double phi = 2 * kPi * u.y;
  return {r * std::cos(phi), r * std::sin(phi)};
}

}  // namespace anamorph
