// A camera's rays over many samples at once, into caller-owned arrays: the pixel-center grid
// of an image (`anamorph rays`, the Python API's Camera.rays) or arbitrary sample positions
// (Camera.generate), and the inverse map of many points (Camera.project). Rays are computed in
// batches of kCameraBatch (the bits of single rays) on every core of the current task arena.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "camera/camera.h"

namespace anamorph {

// Where the rays go: interleaved x, y, z per ray (3 n doubles each), `valid` one byte per ray
// (1 = a ray, 0 = none: its other values are then zero). Null arrays are not written.
struct RayArrays {
  double* org = nullptr;
  double* dir = nullptr;
  double* dorg_du = nullptr;
  double* dorg_dv = nullptr;
  double* ddir_du = nullptr;
  double* ddir_dv = nullptr;
  uint8_t* valid = nullptr;
};

// The samples: image positions u[i], v[i]; optional lens positions (lens_u, lens_v in [0,1),
// default 0.5, 0.5 = the exact pinhole ray) and shutter times (default 0).
struct SampleArrays {
  const double* u = nullptr;
  const double* v = nullptr;
  const double* lens_u = nullptr;
  const double* lens_v = nullptr;
  const double* time = nullptr;
};

// Rays for samples 0..n-1.
void generate_rays(const Camera& cam, size_t n, const SampleArrays& in, const RayArrays& out);

// The rays at the pixel centers ((x + 0.5) / width, (y + 0.5) / height) of a width x height
// image, row-major from the top-left.
void generate_ray_field(const Camera& cam, int width, int height, const RayArrays& out);
// The same rays for the pixels x0 <= x < x1, y0 <= y < y1 of that image only, row-major over the
// rectangle, on the calling thread (a tile's: the render's ray_origin / ray_direction layers, a
// row of `anamorph rays`). The same bits as generate_ray_field's.
void generate_pixel_rays(const Camera& cam, int width, int height, int x0, int y0, int x1, int y1,
                         const RayArrays& out);

// Every image position (u, v) of each of n points (xyz interleaved): point i's positions are
// uv[offsets[i] .. offsets[i + 1]) (two doubles each); offsets has n + 1 entries.
struct Projections {
  std::vector<double> uv;
  std::vector<uint64_t> offsets;
};
Projections project_points(const Camera& cam, size_t n, const double* xyz);

}  // namespace anamorph
