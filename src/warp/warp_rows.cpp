#include "warp/warp_rows.h"

#include <algorithm>

#include "camera/stmap.h"
#include "math/parallel.h"

namespace anamorph {

void warp_rows(const WarpView& v, int y0, int rows, float* rgba) {
  const int W = v.width, H = v.height;
  std::fill(rgba, rgba + size_t(rows) * size_t(W) * 4, 0.0f);
  for (int y = y0; y < y0 + rows; ++y)
    for (int x = 0; x < W; ++x) {
      const auto r = v.camera.generate(CameraSample{{(x + 0.5) / W, (y + 0.5) / H}});
      if (!r) continue;
      const auto f = source_footprint(v.source, *r, W, H);
      if (!f) continue;
      v.texture.lookup(f->uv, f->duv_dx, f->duv_dy, &rgba[(size_t(y - y0) * W + size_t(x)) * 4]);
    }
}

std::vector<float> warp_image(const WarpView& v) {
  std::vector<float> rgba(size_t(v.width) * size_t(v.height) * 4);
  parallel_for_each(0, v.height,
                    [&](int y) { warp_rows(v, y, 1, &rgba[size_t(y) * size_t(v.width) * 4]); });
  return rgba;
}

}  // namespace anamorph
