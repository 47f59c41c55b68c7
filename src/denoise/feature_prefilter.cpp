#include "denoise/feature_prefilter.h"

#include "denoise/variance.h"

namespace anamorph::nfor {

void prefilter_channel(const Planes& a, const Planes& b, const Planes& coverage,
                       const FeatureFilter& filter, Planes& out_a, Planes& out_b,
                       MemoryMeter* meter) {
  Planes var(a.width(), a.height(), 1, meter);
  two_buffer_variance(a, b, coverage, VarianceEstimate{}, var, meter);
  const Planes* in_a[] = {&a};
  const Planes* in_b[] = {&b};
  Planes* o_a[] = {&out_a};
  Planes* o_b[] = {&out_b};
  nl_means({&b, &var, &coverage}, filter.kernel, filter.window_radius, in_a, o_a, meter, true);
  nl_means({&a, &var, &coverage}, filter.kernel, filter.window_radius, in_b, o_b, meter, true);
}

void refilter_features(const Planes& a, const Planes& b, const Planes& coverage,
                       const FeatureFilter& filter, Planes& out, MemoryMeter* meter) {
  const int w = a.width(), h = a.height();
  Planes mean(w, h, 1, meter), var(w, h, 1, meter), one(w, h, 1, meter);
  const VarianceEstimate residual{0.25f, 1, false};
  for (int c = 0; c < a.channels(); ++c) {
    Planes ca(w, h, 1, meter), cb(w, h, 1, meter);
    for (size_t i = 0; i < a.pixels(); ++i) {
      ca.plane(0)[i] = a.plane(c)[i];
      cb.plane(0)[i] = b.plane(c)[i];
      mean.plane(0)[i] = 0.5f * (a.plane(c)[i] + b.plane(c)[i]);
    }
    two_buffer_variance(ca, cb, coverage, residual, var, meter);
    const Planes* in[] = {&mean};
    Planes* o[] = {&one};
    nl_means({&mean, &var, &coverage}, filter.kernel, filter.window_radius, in, o, meter, true);
    for (size_t i = 0; i < a.pixels(); ++i) out.plane(c)[i] = one.plane(0)[i];
  }
}

}  // namespace anamorph::nfor
