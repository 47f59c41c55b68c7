#include "render/coin_layer.h"

#include "camera/coins.h"

namespace anamorph {

ImageLayer coins_layer(const Scene& scene) {
  const int W = scene.render.width, H = scene.render.height;
  const LayerSpec spec = coins_layer_spec();
  ImageLayer l{spec.name, spec.channels, std::vector<float>(size_t(W) * H)};
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      l.data[size_t(y) * W + x] =
          float(coin_overlay(*scene.camera, {(x + 0.5) / W, (y + 0.5) / H}, {1.0 / W, 1.0 / H}));
  return l;
}

LayerSpec coins_layer_spec() { return {"coins", {"A"}}; }

}  // namespace anamorph
