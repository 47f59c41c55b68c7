// This process's threads as the place tiles are rendered: a TileFarm (render/tile_farm.h) whose
// workers are the threads of a task arena. Each thread asks for the next tile, renders it through
// the session (TileSession::render, as an MPI worker does) and hands it back itself, so `done`
// runs on several threads at once. A whole tile's buffer stays with its thread for the next tile
// unless the caller takes it: nothing is allocated per tile, and the memory is still in cache.
#pragma once

#include <tbb/task_arena.h>

#include "render/tile_farm.h"
#include "render/tile_session.h"

namespace anamorph {

class LocalThreads final : public TileFarm {
 public:
  LocalThreads(const TileSession& session, tbb::task_arena& arena)
      : session_(session), arena_(arena) {}
  // `next` must be thread-safe; `done` is called on the thread that rendered the tile.
  void run(const std::function<std::optional<FarmTile>()>& next,
           const std::function<void(FarmResult&)>& done) override;

 private:
  const TileSession& session_;
  tbb::task_arena& arena_;
};

}  // namespace anamorph
