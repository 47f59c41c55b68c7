#include "denoise/variance.h"

#include <algorithm>

#include "math/parallel.h"

namespace anamorph::nfor {

namespace {

// Sums of in over rows [y - r, y + r] ∩ image and columns likewise: first along rows into tmp,
// then along columns into out (each pixel's sum in the same order on any thread count).
void box_sums(const float* in, int w, int h, int r, float* tmp, float* out) {
  parallel_for_each(0, h, [&](int y) {
    const float* row = in + size_t(y) * w;
    for (int x = 0; x < w; ++x) {
      float s = 0.0f;
      for (int i = std::max(0, x - r); i <= std::min(w - 1, x + r); ++i) s += row[i];
      tmp[size_t(y) * w + x] = s;
    }
  });
  parallel_for_each(0, h, [&](int y) {
    float* o = out + size_t(y) * w;
    std::fill_n(o, w, 0.0f);
    for (int j = std::max(0, y - r); j <= std::min(h - 1, y + r); ++j)
      for (int x = 0; x < w; ++x) o[x] += tmp[size_t(j) * w + x];
  });
}

}  // namespace

void two_buffer_variance(const Planes& a, const Planes& b, const Planes& coverage,
                         const VarianceEstimate& how, Planes& out, MemoryMeter* meter) {
  const int w = a.width(), h = a.height();
  const size_t n = a.pixels();
  const float* cov = coverage.plane(0);
  Planes term(w, h, 1, meter), tmp(w, h, 1, meter), count(w, h, 1, meter);
  for (size_t i = 0; i < n; ++i) term.plane(0)[i] = cov[i] > 0.0f ? 1.0f : 0.0f;
  box_sums(term.plane(0), w, h, how.radius, tmp.plane(0), count.plane(0));
  for (int c = 0; c < a.channels(); ++c) {
    const float *pa = a.plane(c), *pb = b.plane(c);
    for (size_t i = 0; i < n; ++i) {
      const float d = pa[i] - pb[i];
      const float weight = how.by_coverage ? cov[i] : 1.0f;
      term.plane(0)[i] = cov[i] > 0.0f ? weight * how.scale * d * d : 0.0f;
    }
    float* o = out.plane(c);
    box_sums(term.plane(0), w, h, how.radius, tmp.plane(0), o);
    for (size_t i = 0; i < n; ++i) {
      const float centre = how.by_coverage ? cov[i] : 1.0f;
      o[i] = cov[i] > 0.0f ? o[i] / (count.plane(0)[i] * centre) : 0.0f;
    }
  }
}

}  // namespace anamorph::nfor
