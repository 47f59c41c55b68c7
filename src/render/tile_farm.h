// Where tiles are rendered. The renderer's tile loop (render/render_run.h) decides which tiles to
// render and in what order, and a farm renders them: this process's threads
// (render/local_threads.h), or, given as RenderOptions::farm, other processes (dist/: MPI ranks),
// each tile handed to whichever asks for work next. A tile's bits do not depend on where it was
// rendered (per-sample RNG, and every place renders through TileSession::render), so a farmed
// render equals a local one. The interface keeps MPI out of the renderer.
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
  // Whole tiles for the outputs: resolved where rendered to these layers and encodings (what the
  // sinks take: 4 bytes a pixel for 8-bit colour, 16 for float RGBA, instead of 32 of sums);
  // null: the sums come back. Owned by the caller until the tile is back.
  const std::vector<LayerRequest>* plan = nullptr;
};

// A tile back from the farm, with what it cost where it ran.
struct FarmResult {
  size_t index = 0;
  std::unique_ptr<TileBuffer> tile;      // a whole tile (a pass's result is in FarmTile::sums)
  std::optional<ResolvedTile> resolved;  // instead, when FarmTile::plan
  TileStats stats;
  double seconds = 0;
  int rank = 0;  // the process that rendered it (an MPI rank)
};

class TileFarm {
 public:
  virtual ~TileFarm() = default;
  // Asks `next` for a tile whenever a process wants work, until it returns nothing, and calls
  // `done` for every tile as it comes back; returns when all are back. (Other processes: `done` on
  // the calling thread; this process's threads: on each thread, for the tiles it rendered.)
  // A pass's `range.active` (the whole image's mask) is sent as the tile's part of it.
  virtual void run(const std::function<std::optional<FarmTile>()>& next,
                   const std::function<void(FarmResult&)>& done) = 0;
};

}  // namespace anamorph
