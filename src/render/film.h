// The film of a whole frame: its tiles' buffers (render/tile_buffer.h), each allocated when a
// render first writes into it, so a film costs what has been rendered, and nothing is cleared
// that no ray will reach. Progressive passes, per-pixel adaptive sampling, the Python module and
// tests keep a frame in a Film; `anamorph render` streams tiles to the output file instead
// (render/frame_output.h) and never holds a whole frame.
#pragma once

#include <memory>
#include <vector>

#include "io/image_io.h"
#include "render/tile_buffer.h"

namespace anamorph {

class Film {
 public:
  Film(int width, int height, std::vector<Aov> aovs, int tile_size = 32);
  int width() const { return grid_.width; }
  int height() const { return grid_.height; }
  const TileGrid& grid() const { return grid_; }
  const std::vector<Aov>& aovs() const { return aovs_; }

  // A tile's buffer, allocated (zeroed) on first use. Distinct tiles may be asked for from
  // different threads at once.
  TileBuffer& tile(size_t index);
  const TileBuffer* tile_if_any(size_t index) const { return tiles_[index].get(); }
  // Puts a finished tile in place (a streamed render into a film).
  void put(size_t index, std::unique_ptr<TileBuffer> tile) { tiles_[index] = std::move(tile); }
  // Takes a tile's buffer out (null if none): the film has no samples there any more.
  std::unique_ptr<TileBuffer> take(size_t index) { return std::move(tiles_[index]); }
  // Back to no samples: every tile's memory is released.
  void clear();

  // One sample at a pixel, through its tile (tests and small tools; the renderer adds into the
  // tile it works on).
  void add(int x, int y, const Color& L, double alpha, const AovSample& a) {
    tile(grid_.index_of(x, y)).add(x, y, L, alpha, a);
  }
  uint32_t samples(int x, int y) const;  // camera samples that went into a pixel
  double standard_error(int x, int y) const;
  Color pixel(int x, int y) const;  // averaged beauty RGB (premultiplied by coverage)
  double alpha(int x, int y) const;

  // Averages: beauty as RGBA (straight alpha), AOV layers as their channels.
  OutputImage output() const;
  // The beauty layer of output() as a PNG stores it (8-bit sRGB, straight alpha), without the
  // float layer in between.
  std::vector<unsigned char> output_rgba8() const;

 private:
  const PixelSum* sum(int x, int y) const;
  TileGrid grid_;
  std::vector<Aov> aovs_;
  std::vector<std::unique_ptr<TileBuffer>> tiles_;
};

}  // namespace anamorph
