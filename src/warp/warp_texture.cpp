#include "warp/warp_texture.h"

#include "io/mip_texture.h"

namespace anamorph {

namespace {

class InMemoryTexture final : public WarpTexture {
 public:
  InMemoryTexture(Image image, bool wrap_u, bool footprint)
      : mip_(std::move(image), wrap_u), footprint_(footprint) {}
  void lookup(Vec2 uv, Vec2 duv_dx, Vec2 duv_dy, float rgba[4]) const override {
    if (footprint_)
      mip_.area(uv, duv_dx, duv_dy, rgba);
    else
      mip_.bilinear(uv, rgba);
  }

 private:
  MipTexture mip_;
  bool footprint_;
};

}  // namespace

std::optional<TextureFilter> texture_filter_named(std::string_view name) {
  if (name == "area") return TextureFilter::Area;
  if (name == "bilinear") return TextureFilter::Bilinear;
  if (name == "aniso") return TextureFilter::Aniso;
  if (name == "bicubic") return TextureFilter::Bicubic;
  return std::nullopt;
}

std::unique_ptr<WarpTexture> make_warp_texture(Image image, bool wrap_u, TextureFilter filter,
                                               int threads) {
  if (filter == TextureFilter::Area || filter == TextureFilter::Bilinear)
    return std::make_unique<InMemoryTexture>(std::move(image), wrap_u,
                                             filter == TextureFilter::Area);
  if (image.channels != 4) {  // (OpenImageIO would give a missing alpha as 0)
    image.pixels = rgba_pixels(std::move(image));
    image.channels = 4;
  }
  return make_oiio_texture(image, wrap_u, filter, threads);
}

}  // namespace anamorph
