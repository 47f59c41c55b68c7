// The renderer: a library call that renders a scene tile by tile (TBB), reporting progress and
// honouring cancellation. Deterministic: each sample draws from an RNG seeded by (pixel, sample
// index, seed), so the result is the same for any thread count, tile size or interruption.
//
// render.time_limit stops any render at whole tiles (never inside one), after at least one tile,
// so a render resumed again and again always finishes.
//
// Two ways to render. render_tiles() renders each tile with all its samples and hands it over:
// memory follows the tiles in flight (what `anamorph render` streams into files). render() keeps
// a whole frame in a Film, in progressive passes (previews, per-pixel adaptive sampling, whose
// stopping rule looks across tile borders).
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <vector>

#include "render/adaptive.h"
#include "render/film.h"
#include "render/frame_output.h"
#include "scene/scene.h"

namespace anamorph {

class Accel;
class Lights;
class TileFarm;
class TileSession;

struct Progress {
  double fraction = 0;  // of all samples
  double seconds = 0;   // since start
  uint64_t rays = 0;    // traced so far
  int pass = 0, passes = 1;
};

// Where an interrupted pass render continues: the film holds every tile after tile_pass[i]
// passes' worth (-1: none), and pass `pass` runs over the pixels `active` leaves on.
struct PassResume {
  int pass = 0;
  std::vector<uint8_t> active;
  std::vector<int> tile_pass;
};

// One tile's work (`render --stats`: per-tile costs, for planning cluster renders).
struct TileTiming {
  size_t index = 0;
  int pass = 0;
  double start = 0, seconds = 0;  // since the render began, and how long the tile took
  uint64_t samples = 0, rays = 0;
  int rank = 0;  // the MPI rank that rendered it (0: this process)
  // A pass render: samples each pixel the pass left on took (samples / pass_samples of the
  // tile's pixels took part); 0 for a whole tile.
  uint32_t pass_samples = 0;
};

struct RenderOptions {
  int threads = 0;  // 0 = all cores
  std::vector<Aov> aovs;
  std::function<void(const Progress&)> on_progress;    // called from worker threads, serialised
  std::function<void(const Film&, int pass)> on_pass;  // after each progressive pass
  const std::atomic<bool>* cancel = nullptr;  // stop within a packet; tiles in flight are lost
  bool progressive = true;                    // passes of 1, 1, 2, 4, ... samples
  // > 0 (uniform sampling, below render.spp): two passes instead, samples [0, split_at) and
  // [split_at, spp), on_pass called after each (the denoiser's half buffers:
  // render/denoise_film.h).
  uint32_t split_at = 0;
  // Textures filtered over the finest footprint (1/8 pixel, RenderJob::footprint_scale) whatever
  // the sample count, instead of each sample's share of the pixel (1/sqrt(spp)): for the
  // denoiser, which averages across pixels itself; a wider footprint at few samples blurs
  // texture detail that both halves then agree on (a bias no filter removes).
  bool finest_footprint = false;
  // When set, used instead of the scene's render settings (spp, view, ...): the denoiser's
  // feature pass (render/denoise_film.h) renders the albedo view at more samples. Kept alive by
  // the caller during the render.
  const RenderSettings* settings = nullptr;
  // Pass renders, for checkpoints: a tile finished pass `pass` (called from its worker thread),
  // and pass `pass` is about to run over the pixels `active` leaves on. `resume` continues.
  std::function<void(size_t tile, int pass, const TileBuffer&)> on_tile_pass;
  std::function<void(int pass, const std::vector<uint8_t>& active)> on_pass_start;
  const PassResume* resume = nullptr;
  std::vector<TileTiming>* tile_times = nullptr;  // when set, every tile rendered is appended
  // When set, tiles are rendered by other processes (dist/: MPI ranks) instead of this one's
  // threads; the result is the same.
  TileFarm* farm = nullptr;
};

struct RenderStats {
  double seconds = 0;
  // samples: camera samples taken (adaptive subdivision: lattice points evaluated, a point shared
  // by neighbouring pixels once; the spp AOV counts it in every pixel that uses it).
  uint64_t rays = 0, samples = 0;
  uint64_t nan_samples = 0;                     // non-finite radiance, dropped
  int nan_x = -1, nan_y = -1, nan_sample = -1;  // the first one in (y, x, sample) order
  bool cancelled = false;                       // by `cancel`: the image is incomplete
  // Stopped by render.time_limit: no tile starts after the limit (tiles in flight finish), so
  // every tile holds whole passes; a pass render stopped in pass `pass` of `passes`.
  bool time_limited = false;
  int pass = 0, passes = 1;
  double mrays_per_second() const { return seconds > 0 ? rays / seconds * 1e-6 : 0; }
};

// A finished tile, from a worker thread (several at once, in roughly increasing index order).
// The sink may take the buffer (move it out); one it leaves is reused for the thread's next tile.
using TileSink = std::function<void(size_t index, std::unique_ptr<TileBuffer>& tile)>;

class Renderer {
 public:
  explicit Renderer(const Scene& scene);  // builds the acceleration structure and lights
  // A renderer whose tiles are all rendered elsewhere (RenderOptions::farm: the head rank of an
  // MPI job). It builds nothing, so the head spends neither the acceleration structure's memory
  // nor its build time; rendering without a farm throws std::logic_error.
  struct FarmOnly {};
  Renderer(const Scene& scene, FarmOnly);
  ~Renderer();
  const Scene& scene() const { return scene_; }
  // A whole frame into `film` (cleared first unless opt.resume), in progressive passes.
  RenderStats render(Film& film, const RenderOptions& opt) const;
  // Every tile of `grid` not marked in `skip` (finished before a checkpoint), each with all its
  // samples, handed to `sink` as it completes. Only for settings streams() accepts.
  RenderStats render_tiles(const TileGrid& grid, const RenderOptions& opt,
                           const std::vector<uint8_t>& skip, const TileSink& sink) const;
  // The same, each tile resolved to `plan` (the layers and encodings the outputs take:
  // FrameOutput::plan) where it was rendered: on this process's threads, or on a farm's workers,
  // which then send 4 or 16 bytes a pixel, not 32.
  RenderStats render_resolved(const TileGrid& grid, const RenderOptions& opt,
                              const std::vector<uint8_t>& skip,
                              const std::vector<LayerRequest>& plan,
                              const std::function<void(ResolvedTile&&)>& sink) const;
  // Whether a tile can be rendered alone: all but per-pixel adaptive sampling.
  static bool streams(const RenderSettings& rs);
  // The state tiles of a `width` x `height` frame of this renderer's scene are rendered with
  // (render/tile_session.h), summing `aovs`; a FarmOnly renderer has none (std::logic_error).
  std::unique_ptr<TileSession> session(std::vector<Aov> aovs, int width, int height,
                                       const std::atomic<bool>* cancel = nullptr,
                                       const RenderSettings* settings = nullptr) const;
  // The settings a render with `opt` uses: opt.settings, or the scene's.
  const RenderSettings& settings(const RenderOptions& opt) const {
    return opt.settings ? *opt.settings : scene_.render;
  }
  // The scene it renders was posed at another frame (scene/scene_pose.h): the acceleration
  // structure moves its instances and rebuilds only deformed meshes and the top level
  // (Accel::repose; anew when that cannot), and the lights are gathered again. The same pixels
  // as a renderer made anew for the posed scene. A FarmOnly renderer has nothing to change.
  void repose();
  const Accel& accel() const { return *accel_; }

 private:
  RenderStats whole_tiles(const TileGrid& grid, const RenderOptions& opt,
                          const std::vector<uint8_t>& skip, const std::vector<LayerRequest>* plan,
                          const TileSink& sink,
                          const std::function<void(ResolvedTile&&)>& resolved) const;
  RenderStats render_passes(Film& film, const RenderOptions& opt) const;
  const Scene& scene_;
  std::unique_ptr<Accel> accel_;
  std::unique_ptr<Lights> lights_;
};

}  // namespace anamorph
