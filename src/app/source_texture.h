// An image as a filtered texture for `anamorph warp`: OpenImageIO's TextureSystem over a
// MIP-mapped, tiled float copy of the image (a temporary file it removes), looked up by source
// position and footprint. Filters: "aniso" (OIIO's anisotropic MIP filter: several probes along
// the footprint ellipse's major axis, bicubic within levels; minified regions do not alias),
// "bilinear" (level 0 only, no footprint: what an STMap node does), "bicubic" (level 0).
#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include "io/image.h"
#include "math/vec.h"

namespace anamorph::app {

enum class TextureFilter { Aniso, Bilinear, Bicubic };

class SourceTexture {
 public:
  // wrap_u: u is periodic (an equirect); v clamps. Sources that do not wrap are black outside
  // [0,1]^2. `threads` (0: all cores) builds the MIP pyramid. Throws std::runtime_error when
  // OIIO fails.
  SourceTexture(const Image& image, bool wrap_u, TextureFilter filter, int threads = 0);
  ~SourceTexture();
  SourceTexture(const SourceTexture&) = delete;
  SourceTexture& operator=(const SourceTexture&) = delete;
  // RGBA at image position uv (v from the top), footprint in uv per target pixel. Thread-safe.
  void lookup(Vec2 uv, Vec2 duv_dx, Vec2 duv_dy, float rgba[4]) const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace anamorph::app
