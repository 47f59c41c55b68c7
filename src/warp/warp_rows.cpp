#include "warp/warp_rows.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "camera/stmap.h"
#include "math/parallel.h"
#include "params/params.h"

namespace anamorph {

void warp_rows(const WarpView& v, int y0, int rows, float* rgba) {
  const int W = v.width, H = v.height;
  std::fill(rgba, rgba + size_t(rows) * size_t(W) * 4, 0.0f);
  CameraSample s[kCameraBatch];
  CameraRayBatch rays;
  for (int y = y0; y < y0 + rows; ++y)
    for (int x0 = 0; x0 < W; x0 += kCameraBatch) {  // (the camera's batch: the same rays)
      const int n = std::min(kCameraBatch, W - x0);
      for (int i = 0; i < n; ++i) s[i].uv = {(x0 + i + 0.5) / W, (y + 0.5) / H};
      v.camera.generate_batch(s, n, &rays);
      for (int i = 0; i < n; ++i) {
        if (!rays.valid[i]) continue;
        const auto f = source_footprint(v.source, rays.ray(i), W, H);
        if (!f) continue;
        v.texture.lookup(f->uv, f->duv_dx, f->duv_dy,
                         &rgba[(size_t(y - y0) * W + size_t(x0 + i)) * 4]);
      }
    }
}

void check_source_aspect(const SourceProjection& source, int width, int height,
                         const std::string& name) {
  const double want = source.aspect(), have = double(width) / height;
  if (std::abs(width - want * height) > 0.5)
    throw ParamError("--source", fmt::format("{} is {}x{} (aspect {:.6g}), but --source {} needs "
                                             "an aspect of {:.6g} (width / height)",
                                             name, width, height, have, source.describe(), want));
}

std::vector<float> warp_image(const WarpView& v) {
  std::vector<float> rgba(size_t(v.width) * size_t(v.height) * 4);
  parallel_for_each(0, v.height,
                    [&](int y) { warp_rows(v, y, 1, &rgba[size_t(y) * size_t(v.width) * 4]); });
  return rgba;
}

}  // namespace anamorph
