#include "render/local_threads.h"

#include "math/parallel.h"

namespace anamorph {

void LocalThreads::run(const std::function<std::optional<FarmTile>()>& next,
                       const std::function<void(FarmResult&)>& done) {
  arena_.execute([&] {
    // One worker per thread of the arena, each taking tiles until there are none.
    const auto workers = size_t(tbb::this_task_arena::max_concurrency());
    parallel_in_order(0, workers, [&](size_t) {
      std::unique_ptr<TileBuffer> spare;  // a whole tile's buffer, for the next one
      while (std::optional<FarmTile> t = next()) {
        FarmResult r = session_.render(*t, spare);
        done(r);
        if (r.tile) spare = std::move(r.tile);  // (what the caller left)
      }
    });
  });
}

}  // namespace anamorph
