// `render --aov coins`: the coins' coverage is drawn from the camera after rendering, so the
// frame is kept in a film; the output gets the coins' layer, and out.coins.png the image with the
// markers drawn in red.
#include <fmt/format.h>

#include <algorithm>

#include "app/frame_job.h"
#include "app/interrupt.h"
#include "app/output_guard.h"
#include "app/render_command.h"
#include "io/image_io.h"
#include "io/image_sink.h"
#include "render/coin_layer.h"
#include "render/film.h"

namespace anamorph::app {

namespace fs = std::filesystem;

namespace {

// The beauty image with the coin markers drawn over it in red, for looking at.
OutputImage with_overlay(const OutputImage& img, const ImageLayer& coins) {
  OutputImage o;
  o.width = img.width;
  o.height = img.height;
  o.metadata = img.metadata;
  ImageLayer b = img.layers[0];
  for (size_t i = 0; i < coins.data.size(); ++i) {
    const float c = coins.data[i];
    const float rgb[3] = {1.0f, 0.1f, 0.05f};
    for (int k = 0; k < 3; ++k)
      b.data[i * 4 + size_t(k)] = b.data[i * 4 + size_t(k)] * (1 - c) + rgb[k] * c;
    b.data[i * 4 + 3] = std::max(b.data[i * 4 + 3], c);
  }
  o.layers.push_back(std::move(b));
  return o;
}

}  // namespace

int render_with_overlay(const RenderSetup& s, const Scene& scene, const Renderer& renderer,
                        double frame, const fs::path& out, const RenderOptions& opt,
                        RenderStats* st) {
  Film film(scene.render.width, scene.render.height, s.aovs, scene.render.tile_size);
  {
    const RenderPhase phase;
    *st = renderer.render(film, opt);
  }
  if (st->cancelled) {
    fmt::print(stderr, "interrupted: {} not written\n", out.string());
    return kInterrupted;
  }
  OutputImage img = film.output();
  img.metadata = frame_metadata(scene, frame);
  img.layers.push_back(coins_layer(scene));
  const fs::path marked = coin_overlay_file(out);
  write_image(marked, with_overlay(img, img.layers.back()));
  if (!s.args.quiet) fmt::print(messages(), "coin overlay written to {}\n", marked.string());
  std::vector<LayerSpec> layers;
  for (const ImageLayer& l : img.layers) layers.push_back({l.name, l.channels});
  const std::vector<fs::path> files = output_files(out, layers);
  for (const fs::path& f : files) write_image(f, img);
  if (files.size() > 1 && !s.args.quiet)
    fmt::print(messages(), "AOVs written to {}\n", files[1].string());
  return kOk;
}

}  // namespace anamorph::app
