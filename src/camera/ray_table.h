// A camera given by samples: a W x H grid of vectors (ray origins or directions) at the pixel
// centers ((i + 1/2) / W, (j + 1/2) / H) of image (u, v), as `anamorph rays` writes them or a
// calibration's per-pixel direction grid gives them (Schöps et al., CVPR 2020), interpolated
// bicubically. Catmull-Rom rather than the cubic B-spline: it passes through every sample (so a
// table reproduces the camera it was sampled from at those pixels) and it is local (a 4 x 4
// stencil), so an invalid sample, a no-ray pixel such as a fisheye's corner, affects only its
// neighbours; an interpolating B-spline would need a prefilter that spreads every sample, and
// every hole, along its whole row and column. C1 continuity is what ray differentials need.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "math/vec.h"

namespace anamorph {

struct RayTableData {
  int width = 0, height = 0;
  std::vector<Vec3> values;  // row-major, top row first
  std::vector<bool> valid;   // empty = all valid
};

class RayTable {
 public:
  // Throws std::invalid_argument for an empty grid, sizes that do not match, non-finite valid
  // samples, or no valid sample at all.
  explicit RayTable(const RayTableData& data);

  // The interpolated vector at image (u, v) with its derivatives; false (no ray) where the
  // bilinear interpolation of the surrounding samples' 0/1 validity is below 1/2 (at a sample:
  // where it is invalid). Invalid samples inside the stencil are
  // replaced, once at load, by linear extrapolation from their valid neighbours, so the field stays
  // smooth up to holes.
  // second (3 entries, may be null): d2/du2, d2/dudv, d2/dv2 (piecewise linear: C1 tables).
  bool eval(double u, double v, Vec3* value, Vec3* du, Vec3* dv, Vec3* second = nullptr) const;

 private:
  const Vec3& at(int i, int j) const {
    return grid_[size_t(j + kPad) * stride_ + size_t(i + kPad)];
  }
  static constexpr int kPad = 2;  // the stencil reaches two samples beyond a cell
  int w_, h_;
  size_t stride_;
  std::vector<Vec3> grid_;  // (w + 4) x (h + 4), padded and filled
  template <bool kSecond>
  void interpolate(int i, int j, double fs, double ft, Vec3* value, Vec3* du, Vec3* dv,
                   Vec3* second) const;
  std::vector<uint8_t> valid_;  // bytes, not vector<bool>: read four times per ray
};

}  // namespace anamorph
