// An image as a texture `anamorph warp` (and Python's anamorph.warp) looks up by source position
// and the target pixel's footprint there. Filters:
// - "area" (default): io/mip_texture.h, in memory: bilinear where the footprint is within a
//   texel, an average along the footprint over a MIP pyramid where the source is minified.
// - "bilinear": the 4 nearest texels of the full-size image, no footprint (an STMap node's).
// - "aniso": OpenImageIO's anisotropic MIP filter (several bicubic probes along the footprint
//   ellipse's major axis), through the plugin (plugins/oiio_texture.h).
// - "bicubic": OpenImageIO's bicubic B-spline on the full-size image, no footprint.
#pragma once

#include <memory>
#include <optional>
#include <string_view>

#include "io/image.h"
#include "math/vec.h"

namespace anamorph {

enum class TextureFilter { Area, Bilinear, Aniso, Bicubic };

// The filter of that name, none for another.
std::optional<TextureFilter> texture_filter_named(std::string_view name);

class WarpTexture {
 public:
  virtual ~WarpTexture() = default;
  // RGBA at image position uv (v from the top), footprint in uv per target pixel. Thread-safe;
  // throws std::runtime_error when OpenImageIO fails.
  virtual void lookup(Vec2 uv, Vec2 duv_dx, Vec2 duv_dy, float rgba[4]) const = 0;
};

// wrap_u: u is periodic (an equirect); v clamps. Sources that do not wrap are black outside
// [0,1]^2. `threads` (0: all cores): OpenImageIO's, for its MIP pyramid. Throws
// std::runtime_error when the OpenImageIO plugin cannot be loaded or fails.
std::unique_ptr<WarpTexture> make_warp_texture(Image image, bool wrap_u, TextureFilter filter,
                                               int threads = 0);

// The OpenImageIO texture (filters Aniso, Bicubic): warp/oiio_texture_source.cpp.
std::unique_ptr<WarpTexture> make_oiio_texture(const Image& image, bool wrap_u,
                                               TextureFilter filter, int threads);

}  // namespace anamorph
