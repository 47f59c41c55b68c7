// A tile's share of the film: per-pixel sums of samples for the beauty pass and any AOVs, over one
// rectangle of the image. A render allocates a tile's buffer when it starts the tile and, when it
// streams its output, frees it once the tile is resolved, so memory follows the tiles in flight,
// not the frame. Every pixel is written by exactly one thread (its tile's), in sample order, so the
// sums are bit-identical for any thread count and tile size.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "math/vec.h"

namespace anamorph {

// The layers a render can sum beside radiance; docs/vision.md defines the depth, camera-space
// and flow conventions.
enum class Aov {
  Albedo,
  Normal,
  Depth,
  Position,
  Id,
  Uv,
  Spp,
  Distance,        // ray distance: |hit - ray origin| (= depth)
  DepthZ,          // along the camera rig's view axis (-z of camera space)
  CameraPosition,  // the hit in camera space (x right, y up, looking along -z)
  FlowForward,     // pixels to where the point is seen at frame + 1, and the valid fraction
  FlowBackward,    // the same toward frame - 1
  Motion,          // Cycles' Vector pass: pixels to frame - 1 (x, y up) and from frame + 1 (z, w)
  RayOrigin,       // the pixel centre's camera ray, world space: every pixel, hit or not
  RayDirection,    // (set per pixel by set_values, not summed over hits)
};
// Layers that hold one value a pixel whatever its samples hit (the pixel-centre camera ray).
inline bool aov_is_per_pixel(Aov a) { return a == Aov::RayOrigin || a == Aov::RayDirection; }

struct AovInfo {
  Aov aov;
  const char* name;
  std::vector<std::string> channels;
  const char* definition;  // what the values are, with units (docs, the EXR's header)
};
const std::vector<AovInfo>& aov_table();
// Parses "albedo,normal,depth"; throws std::invalid_argument naming a bad entry.
std::vector<Aov> parse_aovs(const std::string& list);
const AovInfo& aov_info(Aov a);
// Floats one pixel of these AOVs takes.
size_t aov_floats(const std::vector<Aov>& aovs);
// Whether these AOVs look at frame + 1 (step 1) or frame - 1 (step -1): flow or motion layers.
bool aovs_need_frame(const std::vector<Aov>& aovs, int step);

// What one camera sample contributes to the AOVs (valid only when `hit`).
struct AovSample {
  bool hit = false;
  Color albedo;
  Vec3 normal, position;
  double depth = 0;
  double id = -1;
  Vec2 uv;
  double depth_z = 0;    // DepthZ (Distance is `depth`)
  Vec3 position_camera;  // CameraPosition
  // Toward frame + 1 [0] and frame - 1 [1], in pixels: where the moved point is seen minus
  // where it is now, when `moved` (it has an image there); `flow_valid` when moreover it is
  // not hidden there (FlowForward, FlowBackward; Motion takes every moved sample).
  Vec2 flow[2];
  bool moved[2] = {false, false};
  bool flow_valid[2] = {false, false};
};

struct TileRect {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  int width() const { return x1 - x0; }
  int height() const { return y1 - y0; }
  size_t pixels() const { return size_t(width()) * size_t(height()); }
};

// The image cut into square tiles, row by row (the last row and column may be narrower).
struct TileGrid {
  TileGrid(int width, int height, int tile_size);
  int width, height, size, cols, rows;
  size_t count() const { return size_t(cols) * size_t(rows); }
  TileRect rect(size_t index) const;
  size_t index_of(int x, int y) const { return size_t(y / size) * size_t(cols) + size_t(x / size); }
};

// Float sums: a pixel's samples are at most a few million, and their sum's relative rounding
// (n * 2^-24 at worst, far less in practice) is below what an 8-bit or half-float output keeps.
struct PixelSum {
  float rgb[3];
  float alpha;
  float lum2;     // sum of squared luminance (variance estimate)
  uint32_t n;     // terms in the sums
  uint32_t hits;  // samples that hit a surface (AOV averages)
  uint32_t spp;   // camera samples taken (equals n for uniform sampling)
};
static_assert(sizeof(PixelSum) == 32);

class TileBuffer {
 public:
  TileBuffer(const TileRect& rect, const std::vector<Aov>& aovs);
  // Zeroed for another rectangle, keeping the storage (a thread's next tile: no allocation, and
  // the memory is still in cache).
  void reset(const TileRect& rect);
  const TileRect& rect() const { return rect_; }
  const std::vector<Aov>& aovs() const { return aovs_; }

  // One camera sample at image pixel (x, y): radiance, coverage (0 for "no ray") and AOV values.
  // Inline: one call per camera sample, and most renders have no AOV layers.
  void add(int x, int y, const Color& L, double alpha, const AovSample& a) {
    PixelSum& p = at(x, y);
    const double l = luminance(L);
    p.rgb[0] += float(L.x);
    p.rgb[1] += float(L.y);
    p.rgb[2] += float(L.z);
    p.alpha += float(alpha);
    p.lum2 += float(l * l);
    p.n++;
    p.spp++;
    if (aov_floats_ > 0 && a.hit) add_aovs(x, y, a);
  }
  // A pixel finished elsewhere (adaptive subdivision): its value and how many samples it took.
  void set(int x, int y, const Color& L, double alpha, uint32_t spp, const AovSample& a);

  const PixelSum& at(int x, int y) const { return px_[index(x, y)]; }
  PixelSum& at(int x, int y) { return px_[index(x, y)]; }
  // data() + offset, not &aov_[i]: with no AOVs the vector is empty and [0] would bind a null.
  const float* aov_at(int x, int y) const { return aov_.data() + index(x, y) * aov_floats_; }
  size_t aov_floats() const { return aov_floats_; }

  // Layer `layer`'s (aovs()[layer], a per-pixel layer) values at a pixel, written as they are.
  void set_values(int x, int y, size_t layer, const float* values);

  // Raw storage, for checkpoints: the pixel sums and the AOV sums, row-major over the rect.
  std::vector<PixelSum>& sums() { return px_; }
  std::vector<float>& aov_sums() { return aov_; }
  const std::vector<PixelSum>& sums() const { return px_; }
  const std::vector<float>& aov_sums() const { return aov_; }

  // Resolved values of one pixel: beauty as straight RGBA (no-ray samples are transparent, not
  // black), and each AOV layer's channels in aov_table order.
  // Straight (un-premultiplied) colour: no-ray samples are transparent, not black. Inline: it
  // runs for every pixel written.
  void beauty_rgba(int x, int y, float* out) const {
    const PixelSum& p = at(x, y);
    const float n = p.n ? float(p.n) : 1.0f;
    const float inv = p.alpha > 0 ? 1.0f / p.alpha : 0.0f;
    for (int c = 0; c < 3; ++c) out[c] = p.rgb[c] * inv;
    out[3] = p.alpha / n;
  }
  void aov_values(int x, int y, float* out) const;  // aov_floats() values
  // The resolved values of one AOV layer (aovs()[layer]) at a pixel: its channels.
  void aov_layer_values(int x, int y, size_t layer, float* out) const;
  // Standard error of the pixel's mean luminance (per-pixel adaptive sampling).
  double standard_error(int x, int y) const;

 private:
  size_t index(int x, int y) const {
    return size_t(y - rect_.y0) * size_t(rect_.width()) + size_t(x - rect_.x0);
  }
  void add_aovs(int x, int y, const AovSample& a);
  TileRect rect_;
  std::vector<Aov> aovs_;
  std::vector<size_t> aov_offsets_;  // per layer: its first float in a pixel's AOV sums
  size_t aov_floats_;
  std::vector<PixelSum> px_;  // zeroed: a new tile has no samples
  std::vector<float> aov_;
};

}  // namespace anamorph
