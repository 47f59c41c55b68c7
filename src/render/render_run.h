// One render call's shared state and its tile loop (internal to the renderer): the options, the
// threads, the time budget, progress and statistics, and sweep(), the one loop through which
// every tile of every render goes.
//
// What differs between renders is a parameter of the loop, never a copy of it:
// - *what* is rendered: a TileWork, whole tiles with all their samples (streamed renders, the
//   lattice) or one pass of a pass render (progressive passes, per-pixel adaptive sampling); it
//   says which tiles need no work, describes each tile to render, and takes each one back;
// - *where* it is rendered: a TileFarm, this process's threads (render/local_threads.h) or other
//   processes (RenderOptions::farm, dist/: MPI ranks), both rendering through TileSession.
// The loop hands tiles out in increasing index order, skips those the work says are settled,
// stops at cancellation or at the time limit (no tile starts once it is spent; tiles in flight
// finish), records each tile's cost and reports progress.
#pragma once

#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>

#include "render/renderer.h"
#include "render/tile_farm.h"

namespace anamorph {

class LocalThreads;
class TileSession;

// What one sweep over a frame's tiles renders, and what becomes of each tile.
class TileWork {
 public:
  virtual ~TileWork() = default;
  virtual size_t count() const = 0;
  // Tile i needs no work here (a checkpoint holds it; no pixel of it takes samples): it counts
  // as done. Asked in increasing order, one call at a time.
  virtual bool settled(size_t i) = 0;
  // Tile i as the place that renders it needs it. Called for distinct tiles from several threads
  // at once (a pass tile's buffer is allocated by the thread that renders it).
  virtual FarmTile request(size_t i) = 0;
  // A tile back from where it was rendered; on that thread, several at once.
  virtual void back(FarmResult& r) = 0;
  int pass = 0, passes = 1;  // for progress and the tile costs
};

class RenderRun {
 public:
  // `session`: the tiles' shared state when this process renders them; null with a farm.
  RenderRun(const RenderOptions& opt, std::unique_ptr<const TileSession> session,
            double time_limit);
  ~RenderRun();
  // The tile loop: every tile of `work` that is not settled, rendered where the options say.
  void sweep(TileWork& work);

  const RenderOptions& opt;
  tbb::task_arena arena;
  bool cancelled() const { return opt.cancel && opt.cancel->load(std::memory_order_relaxed); }
  bool out_of_time() const { return out_of_time_.load(); }
  // render.time_limit spent (after at least one tile started)?
  bool past_time_limit() const;
  // A tile's work is done: its statistics into the render's, progress to the caller.
  void tile_done(const TileStats& st, uint64_t work, int pass, int passes);
  void add_done_work(uint64_t work) { work_done_ += work; }  // before the loop: resumed tiles
  void set_work_total(uint64_t total) { work_total_ = total; }
  uint32_t pass_samples = 0;  // samples per pixel of the pass running (0: whole tiles)
  RenderStats stats;
  RenderStats finish();

 private:
  bool may_start_tile();
  void record_time(size_t index, int pass, double seconds, const TileStats& st, int rank);
  void merge(const TileStats& st);

  const std::chrono::steady_clock::time_point t0_ = std::chrono::steady_clock::now();
  const std::unique_ptr<const TileSession> session_;
  std::unique_ptr<LocalThreads> local_;
  const double time_limit_;
  std::atomic<size_t> started_{0};
  std::atomic<bool> out_of_time_{false};
  std::mutex mu_;
  uint64_t work_done_ = 0, rays_done_ = 0, work_total_ = 1;
};

}  // namespace anamorph
