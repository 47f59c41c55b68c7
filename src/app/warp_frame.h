// One frame of `anamorph warp`: the camera's image, each pixel's ray direction looked up in the
// source projection and the texture filtered there by the ray's footprint, written through the
// output's sink (io/image_sink.h) strip by strip from the top. Only a batch of strips (a few
// per thread) is in memory at once, so an 8K frame costs its source texture's cache and those
// strips, not the whole output (docs/compositing.md, "Memory").
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <string>

#include "app/source_texture.h"
#include "camera/camera.h"
#include "camera/source_projection.h"

namespace anamorph::app {

struct WarpView {
  const Camera& camera;
  const SourceProjection& source;
  const SourceTexture& texture;
  int width, height;
};

// Rows [y0, y0 + rows) of the camera's image into `rgba` (rows x width x 4 floats, straight
// colour, alpha 1 where the pixel has a ray the source shows, all 0 elsewhere). Thread-safe.
void warp_rows(const WarpView& v, int y0, int rows, float* rgba);

// The frame written to `file` (its sink chosen by the extension), committed when complete: an
// interruption or error before leaves no file. `progress` (may be empty) gets the fraction done
// after each batch of strips; `committed` (may be empty) runs right after the commit (a sequence
// updates its interruption note there).
void warp_to_file(const WarpView& v, const std::filesystem::path& file,
                  const std::map<std::string, std::string>& metadata,
                  const std::function<void(double)>& progress,
                  const std::function<void()>& committed = nullptr);

}  // namespace anamorph::app
