// The `coins` output layer: where each coin's (uc, vc) marker and radius outline fall in the
// image. Drawn from the camera after rendering (not sampled), so any render can ask for it.
#pragma once

#include "io/image_io.h"
#include "io/image_sink.h"
#include "scene/scene.h"

namespace anamorph {

// One channel "A" (coverage in [0, 1]) at the scene's image size.
ImageLayer coins_layer(const Scene& scene);
// Its name and channel, as outputs see it.
LayerSpec coins_layer_spec();

}  // namespace anamorph
