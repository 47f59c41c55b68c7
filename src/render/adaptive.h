// Adaptive antialiasing.
//
// Whitted (the paper's method, POV-Ray's method 2 in spirit): samples sit on a lattice that
// refines each pixel down to 2^aa_depth steps. Pixel corners are sampled first and shared with
// neighbouring pixels (and, since every lattice point's random numbers depend only on its
// position, with neighbouring tiles: no seams). A square whose four corners differ by more than
// aa_threshold is split in four, recursively. A lattice point filters textures over the spacing of
// the coarsest level it belongs to (pixel corners over a pixel, midpoints over half a pixel...),
// a function of its position alone, so shared points agree. Distortion-driven: the pixel corners'
// ray differentials give each pixel's footprint (the largest of its corners'); pixels larger than
// the image's median footprint (estimated before rendering from every 8th corner of every 8th
// row), and pixels along whose edges the ray field jumps, start split, so stretched regions get
// more samples before any contrast is seen.
//
// Per pixel ("pixel", path's adaptive sampling): passes of min_spp, then doubling; after each, a
// pixel stops once its error estimate and its neighbours' are small (StopRule).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "camera/camera.h"
#include "render/film.h"
#include "render/render_job.h"
#include "scene/scene.h"

namespace anamorph {

struct PixelResult {
  Color L;
  double alpha = 0;
  uint32_t samples = 0;
  uint32_t nans = 0;
};

// Per-thread scratch space, reused across tiles.
struct AdaptiveWorkspace {
  struct Point {
    Color L;
    float alpha = 0;
    uint32_t stamp = 0;  // pixel that last counted this point
    uint32_t tile = 0;   // the tile that evaluated it: points of earlier tiles are stale
    bool nan = false;
  };
  // A tile's lattice, reused without clearing (a tile touches few of its points: clearing the
  // whole lattice moved 0.7 MB per tile at depth 2, 2.6 MB at depth 3).
  std::vector<Point> points;
  uint32_t tile = 0, stamp = 0;  // counters across tiles, so stale values never match
  // Level-by-level refinement: the squares of one level and the next, the points to evaluate.
  struct Square {
    int lx, ly, size, forced;
  };
  std::vector<Square> level, next_level;
  std::vector<uint32_t> pending;      // lattice indices
  std::vector<uint8_t> pixel_splits;  // per pixel of the tile: its square splits
  // The distortion map: each pixel corner's ray field at distance D, each pixel's forced levels.
  struct Corner {
    Vec3 pos, pu, pv;  // org + D dir, and its derivatives per pixel step
    double s = 0;      // footprint
    bool valid = false;
  };
  std::vector<Corner> corners;
  std::vector<uint8_t> forced;
};

class AdaptiveGrid {
 public:
  AdaptiveGrid(const Camera& cam, int width, int height, const RenderSettings& rs,
               const Bounds3& scene_bounds);

  // Lattice points in batches of kCameraBatch (camera batches and ray packets): uv, the key their
  // random numbers come from, and the lattice spacing each stands for, in pixels (textures filter
  // over it). Lanes with use[i] false are not wanted. A lane's result must depend on that lane
  // alone, not on which other points share its batch.
  // With `cam` not null, the batch's camera rays are left there (the corners' differentials give
  // the distortion map).
  using EvalBatch =
      std::function<void(const Vec2* uv, const uint64_t* keys, const double* footprints,
                         const bool* use, SampleResult* out, uint64_t& rays, CameraRayBatch* cam)>;
  using Emit = std::function<void(int x, int y, const PixelResult&)>;
  // Pixel corners first, in 4x4 blocks aligned to the image; then level by level, every point the
  // squares split at that level need, in batches. `samples` counts the points evaluated.
  void render_tile(int x0, int y0, int x1, int y1, AdaptiveWorkspace& ws, const EvalBatch& eval,
                   const Emit& emit, uint64_t& rays, uint64_t& samples) const;

 private:
  struct TileRun;
  // Levels each pixel of the tile is split to before contrast is looked at, from its corners.
  void distortion_map(int x0, int y0, int x1, int y1, AdaptiveWorkspace& ws) const;

  int w_, h_, depth_, steps_;  // steps_ = 2^depth_ lattice steps per pixel
  double threshold_;
  bool distortion_ = false;
  double distance_ = 1, median_ = 0;  // D, and the median corner footprint
};

// When a pixel of per-pixel adaptive sampling stops. With s the standard deviation of its
// samples' luminance, n their number and m their mean, a pixel is done when
//   s * n^-(0.5 + n_power) <= threshold * sqrt(m + 1e-4)
// and so is every neighbour in its 3x3 neighbourhood, each against neighbour_factor * threshold.
// Noisy integrands (path): n_power 0, the standard error of the mean, the same relative noise in
// every pixel, as Cycles does. Deterministic ones (whitted): the error of an Owen-scrambled
// Sobol' estimate of a pixel holding edges falls like s * n^-3/4, and the image's squared error
// for a given number of samples is least when every pixel stops where its error's decrease per
// added sample, about e^2 / n, is the same: e / sqrt(n) = s * n^-5/4 (n_power 0.75). Its first
// passes have two samples, which may both miss a pixel's detail, so neighbours keep a pixel
// going, but only when they are clearly (4x) above the threshold.
struct StopRule {
  double threshold = 0.01;
  double n_power = 0;
  double neighbour_factor = 1;
  static StopRule noisy(double t) { return {t, 0, 1}; }
  static StopRule deterministic(double t) { return {t, 0.75, 4}; }
};

// Per-pixel adaptive sampling: recomputes which pixels still need samples; returns how many do.
size_t update_active(const Film& film, const StopRule& rule, std::vector<uint8_t>* active);

}  // namespace anamorph
