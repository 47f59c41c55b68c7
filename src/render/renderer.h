// The renderer: a library call that renders a scene into a film tile by tile (TBB), in
// progressive passes, reporting progress and honouring cancellation. Deterministic: each sample
// draws from an RNG seeded by (pixel, sample index, seed).
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <vector>

#include "render/adaptive.h"
#include "render/film.h"
#include "scene/scene.h"

namespace anamorph {

class Accel;
class Lights;

struct Progress {
  double fraction = 0;  // of all samples
  double seconds = 0;   // since start
  uint64_t rays = 0;    // traced so far
  int pass = 0, passes = 1;
};

struct RenderOptions {
  int threads = 0;  // 0 = all cores
  std::vector<Aov> aovs;
  std::function<void(const Progress&)> on_progress;    // called from worker threads, serialised
  std::function<void(const Film&, int pass)> on_pass;  // after each progressive pass
  const std::atomic<bool>* cancel = nullptr;
  bool progressive = true;  // passes of 1, 1, 2, 4, ... samples
};

struct RenderStats {
  double seconds = 0;
  // samples: camera samples taken (adaptive subdivision: lattice points evaluated, a point shared
  // by neighbouring pixels once; the spp AOV counts it in every pixel that uses it).
  uint64_t rays = 0, samples = 0;
  uint64_t nan_samples = 0;                     // non-finite radiance, dropped
  int nan_x = -1, nan_y = -1, nan_sample = -1;  // the first one in (y, x, sample) order
  bool cancelled = false;
  double mrays_per_second() const { return seconds > 0 ? rays / seconds * 1e-6 : 0; }
};

class Renderer {
 public:
  explicit Renderer(const Scene& scene);  // builds the acceleration structure and lights
  ~Renderer();
  RenderStats render(Film& film, const RenderOptions& opt) const;
  const Accel& accel() const { return *accel_; }

 private:
  struct Job;
  const Scene& scene_;
  std::unique_ptr<Accel> accel_;
  std::unique_ptr<Lights> lights_;
};

}  // namespace anamorph
