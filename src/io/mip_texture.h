// An image in memory as a texture filtered by a footprint: RGBA floats and a pyramid of 2x2 box
// reductions (MIP levels), looked up by image position (u left to right, v top to bottom, pixel
// centers at (x + 0.5) / W, as the camera contract's) and by how far one target pixel reaches
// there. What `anamorph warp` filters with by default (docs/compositing.md, "Filters").
//
// - bilinear(): level 0 only, the 4 nearest texels (what an STMap node does).
// - area(): where the footprint (the parallelogram the derivatives span) is no longer than one
//   texel, bilinear on level 0, which is then exact up to reconstruction; where it is longer
//   (the source minified), the average of a grid of bilinear probes over the footprint (along
//   its major and minor axes, spaced at most a texel apart) on a level whose texels are a
//   quarter of the minor axis (blended between two levels; at most 16 probes an axis, a
//   coarser level beyond), so minified regions do not alias and magnified ones are not blurred.
//   Continuous at one texel (the probes spread over the footprint less one texel).
//
// Outside the image: u wraps when the texture wraps (an equirect; v then clamps), else texels
// outside are 0 (all four channels). Lookups are const and thread-safe; their result does not
// depend on threads.
#pragma once

#include <vector>

#include "io/image.h"
#include "math/vec.h"

namespace anamorph {

// The image's pixels as RGBA (grey to R = G = B; alpha 1 where it has none), moved when they are.
std::vector<float> rgba_pixels(Image&& image);

class MipTexture {
 public:
  // Takes the image's pixels (any channel count: 1 grey, 3 RGB, 4 RGBA); levels are built on
  // `threads`-independent rows in parallel.
  MipTexture(Image image, bool wrap_u);
  int width() const { return levels_[0].width; }
  int height() const { return levels_[0].height; }
  int levels() const { return int(levels_.size()); }

  void bilinear(Vec2 uv, float rgba[4]) const;
  // duv_dx, duv_dy: the change of uv per target pixel along x and y.
  void area(Vec2 uv, Vec2 duv_dx, Vec2 duv_dy, float rgba[4]) const;

 private:
  struct Level {
    int width = 0, height = 0;
    std::vector<float> rgba;  // width * height * 4
  };
  // Adds weight x the bilinear value of level `l` at uv to sum.
  void add_bilinear(const Level& l, double u, double v, float weight, float sum[4]) const;
  // The footprint in level-0 pixels: its length along its major axis (a unit vector) and
  // across it.
  struct Footprint {
    double major, minor;
    Vec2 axis;
  };
  // The average of a grid of probes over the footprint on level `li`, spaced at most a texel
  // apart, times weight, added to sum.
  void add_probes(int li, Vec2 uv, const Footprint& f, float weight, float sum[4]) const;
  std::vector<Level> levels_;
  bool wrap_u_;
};

}  // namespace anamorph
