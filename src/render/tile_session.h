// One render's shared state for rendering single tiles: the job, the packet builder and, for the
// paper's adaptive supersampling, its lattice. Built once per frame; its methods are const and
// may run on many threads at once. The renderer's loops and an MPI worker rank (dist/) render
// through it, so a tile gets the same bits wherever it is rendered.
#pragma once

#include <atomic>
#include <memory>
#include <vector>

#include "render/integrator.h"
#include "render/render_job.h"
#include "render/tile_buffer.h"
#include "render/tile_sampler.h"

namespace anamorph {

class AdaptiveGrid;
class Renderer;

class TileSession {
 public:
  // `cancel`: when set, samples stop within a packet (the tile is then incomplete).
  TileSession(const Renderer& renderer, bool aovs, int width, int height,
              const std::atomic<bool>* cancel = nullptr);
  ~TileSession();
  // Every sample of the tile (uniform sampling, or the adaptive lattice) into `tile`, zeroed by
  // the caller.
  void whole(TileBuffer& tile, TileStats& st) const;
  // The range's samples added to `tile`'s sums (one pass of a pass render).
  void samples(const SampleRange& range, TileBuffer& tile, TileStats& st) const {
    sampler_.sample(range, tile, st);
  }
  // Camera samples one pixel of a whole tile stands for in a render's progress.
  static uint64_t whole_work_per_pixel(const RenderSettings& rs);
  const RenderJob& job() const { return job_; }

 private:
  const RenderSettings& rs_;
  RenderContext ctx_;
  RenderJob job_;
  TileSampler sampler_;
  std::unique_ptr<AdaptiveGrid> lattice_;
  struct Workspaces;
  std::unique_ptr<Workspaces> spaces_;  // per thread (the lattice's)
};

}  // namespace anamorph
