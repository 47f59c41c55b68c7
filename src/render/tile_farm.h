// Tiles rendered by other processes. A render given a TileFarm (RenderOptions::farm) renders no
// tile itself: it decides which tiles to render and in what order, as it always does, and the
// farm hands each one to whichever process asks for work next (dist/: MPI ranks), giving back the
// tile's sums. The tiles' bits do not depend on where they were rendered (per-sample RNG), so a
// farmed render equals a local one. The interface keeps MPI out of the renderer.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "render/frame_output.h"
#include "render/tile_buffer.h"
#include "render/tile_sampler.h"

namespace anamorph {

struct FarmTile {
  size_t index = 0;
  TileRect rect;
  int image_width = 0;  // of `range.active`, the whole image's mask
  // Whole tiles: every sample (uniform, or the adaptive lattice) into a new buffer. Otherwise
  // one pass of a pass render: `range`'s samples added to `sums`, the tile's sums so far, in
  // place (it must stay put until the tile is back).
  bool whole = true;
  SampleRange range;
  TileBuffer* sums = nullptr;
  // Whole tiles for output files: resolved where rendered into the files' formats (8-bit sRGB for
  // a PNG, floats for an EXR), 4 or 16 bytes a pixel to send instead of 32 of sums.
  bool png = false, exr = false;
};

// A tile back from the farm, with what it cost where it ran.
struct FarmResult {
  size_t index = 0;
  std::unique_ptr<TileBuffer> tile;      // a whole tile (a pass's result is in FarmTile::sums)
  std::optional<ResolvedTile> resolved;  // instead, when FarmTile::png or exr
  TileStats stats;
  double seconds = 0;
  int rank = 0;  // the process that rendered it (an MPI rank)
};

class TileFarm {
 public:
  virtual ~TileFarm() = default;
  // Asks `next` for a tile whenever a process wants work, until it returns nothing, and calls
  // `done` (on the calling thread) for every tile as it comes back; returns when all are back.
  // A pass's `range.active` (the whole image's mask) is sent as the tile's part of it.
  virtual void run(const std::function<std::optional<FarmTile>()>& next,
                   const std::function<void(FarmResult&)>& done) = 0;
};

}  // namespace anamorph
