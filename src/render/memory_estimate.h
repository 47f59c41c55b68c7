// What a render will allocate, estimated before it does, against what the machine can give: a
// frame too big for the machine is refused up front with the reason (exit 2), never a
// std::bad_alloc half-way through. The figures follow the layouts in docs/architecture.md
// ("Film"): exact for the film and the strips, approximate for the acceleration structure.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace anamorph {

struct Scene;

struct RenderShape {
  int width = 0, height = 0, tile_size = 32, threads = 1;
  size_t aov_floats = 0;     // per pixel
  bool whole_film = false;   // the frame kept in a film (pass renders), not streamed tiles
  bool active_mask = false;  // per-pixel adaptive sampling's one byte a pixel
  // What a pixel of an output strip (a tile row) costs the sinks, their copies included
  // (io/image_sink.h: strip_bytes_per_pixel): 8 for a PNG, 16 + 4 * aov_floats for an EXR.
  size_t strip_bytes_per_pixel = 0;
  bool output_image = false;  // a whole output image as well (the coin overlay)
  // Denoised (render/denoise_film.h): the film is whole, with the denoiser's layers in
  // aov_floats, and the other half's film and the denoiser's planes come on top.
  bool denoise = false;
};

struct MemoryNeed {
  std::vector<std::pair<std::string, uint64_t>> parts;  // what, bytes
  uint64_t total() const;
  std::string describe() const;  // "film 64.0 GiB (65536 x 65536 pixels x 32 B), ..."
};

MemoryNeed estimate_render_memory(const Scene& scene, const RenderShape& shape);

// The check every front end makes before a render allocates (the CLI's render, Python's
// Scene.render): none when `need` fits in available_memory() (or that is unknown), else "this
// render needs about 128.0 GiB (film ... 128.0 GiB, ...), but 3.1 GiB is available". `what`
// names the work with its verb ("this render needs", "these rays need").
std::optional<std::string> memory_shortfall(const MemoryNeed& need,
                                            const std::string& what = "this render needs");

// Bytes this process can still allocate without swapping: MemAvailable, lowered by an address-
// space or data limit (ulimit -v/-d) if one is set. 0 when unknown.
uint64_t available_memory();

std::string format_bytes(uint64_t bytes);  // "1.5 GiB", "27.0 MiB", "512 B"

}  // namespace anamorph
