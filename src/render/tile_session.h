// One render's shared state for rendering single tiles: the job, the packet builder and, for the
// paper's adaptive supersampling, its lattice. Built once per frame (Renderer::session); its
// methods are const and may run on many threads at once. Every tile of every render goes through
// render(): on this process's threads (render/local_threads.h) or on an MPI worker rank (dist/),
// so a tile gets the same bits wherever it is rendered.
#pragma once

#include <atomic>
#include <memory>
#include <vector>

#include "render/integrator.h"
#include "render/render_job.h"
#include "render/tile_buffer.h"
#include "render/tile_farm.h"
#include "render/tile_sampler.h"

namespace anamorph {

class AdaptiveGrid;
class Accel;
class Lights;

class TileSession {
 public:
  // What the tiles are rendered from: a scene with its acceleration structure and lights (a
  // Renderer's).
  struct World {
    const Scene& scene;
    const Accel& accel;
    const Lights& lights;
    const RenderSettings* settings = nullptr;  // instead of scene.render when set
  };
  // `aovs`: the layers a tile's buffer sums. `cancel`: when set, samples stop within a packet
  // (the tile is then incomplete).
  TileSession(const World& world, std::vector<Aov> aovs, int width, int height,
              const std::atomic<bool>* cancel = nullptr);
  ~TileSession();
  // One tile as a farm hands it out, rendered on the calling thread. A whole tile: every sample
  // into `buffer` (allocated, or reset when there is one), then resolved to `t`'s layers, or
  // handed over in the result's `tile` (otherwise `buffer` stays for the thread's next tile). A
  // pass: the range's samples added to `*t.sums` in place.
  FarmResult render(const FarmTile& t, std::unique_ptr<TileBuffer>& buffer) const;
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
  std::vector<Aov> aovs_;
  RenderContext ctx_;
  RenderJob job_;
  TileSampler sampler_;
  std::unique_ptr<AdaptiveGrid> lattice_;
  struct Workspaces;
  std::unique_ptr<Workspaces> spaces_;  // per thread (the lattice's)
};

}  // namespace anamorph
