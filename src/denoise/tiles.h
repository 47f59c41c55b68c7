// Rectangles and the tiles the denoiser's passes work on. Tiles are fixed by the image size
// and the window radius only, never by the thread count, so every pass does the same arithmetic
// in the same order on any number of threads.
#pragma once

#include <algorithm>
#include <cstddef>

namespace anamorph::nfor {

struct Rect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  int width() const { return x1 - x0; }
  int height() const { return y1 - y0; }
  size_t area() const { return size_t(width()) * size_t(height()); }
};

// The image cut into square tiles of `size` pixels, row by row (the last row and column may be
// narrower).
struct TileLayout {
  TileLayout(int width, int height, int size)
      : width(width),
        height(height),
        size(size),
        cols((width + size - 1) / size),
        rows((height + size - 1) / size) {}
  int width, height, size, cols, rows;
  size_t count() const { return size_t(cols) * size_t(rows); }
  Rect rect(int col, int row) const {
    return {col * size, row * size, std::min(width, (col + 1) * size),
            std::min(height, (row + 1) * size)};
  }
  Rect rect(size_t index) const {
    return rect(int(index % size_t(cols)), int(index / size_t(cols)));
  }
};

// Tile side: 32 pixels, or more for a wide window. The collaborative regression writes each
// tile's windows into a border `window_radius` wide around it; with a side of at least twice the
// radius, tiles two apart in x and in y never write the same pixel (regression.cpp).
inline int tile_size_for(int window_radius) { return std::max(32, 2 * window_radius); }

}  // namespace anamorph::nfor
