#include "denoise/selection.h"

namespace anamorph::nfor {

void estimate_mse(const Planes& a, const Planes& b, const Planes& var_a, const Planes& var_b,
                  const Candidate& f, const Planes& coverage, Planes& mse) {
  const size_t n = a.pixels();
  const float* cov = coverage.plane(0);
  for (int c = 0; c < 3; ++c) {
    const float *pa = a.plane(c), *pb = b.plane(c), *va = var_a.plane(c), *vb = var_b.plane(c);
    const float *fa = f.a.plane(c), *fb = f.b.plane(c);
    float* o = mse.plane(c);
    for (size_t i = 0; i < n; ++i) {
      const float ea = pb[i] - fa[i], eb = pa[i] - fb[i], d = fa[i] - fb[i];
      const float m = 0.5f * ((ea * ea - vb[i]) + (eb * eb - va[i])) - 0.25f * d * d;
      o[i] = cov[i] > 0.0f ? m : 0.0f;
    }
  }
}

namespace {

// Smooths every plane set of `sets` in place with one set of weights.
void smooth_all(std::vector<Planes>& sets, const Smoother& s, MemoryMeter* meter) {
  std::vector<Planes> out;
  std::vector<const Planes*> in_ptr;
  std::vector<Planes*> out_ptr;
  for (Planes& p : sets) out.emplace_back(p.width(), p.height(), p.channels(), meter);
  for (size_t i = 0; i < sets.size(); ++i) {
    in_ptr.push_back(&sets[i]);
    out_ptr.push_back(&out[i]);
  }
  nl_means(s.guide, s.kernel, s.window_radius, in_ptr, out_ptr, meter);
  sets = std::move(out);
}

}  // namespace

void select_and_blend(std::vector<Candidate>& candidates, std::vector<Planes>& mse,
                      const Smoother& smooth, MemoryMeter* meter) {
  if (candidates.size() < 2) {
    mse.clear();
    return;
  }
  smooth_all(mse, smooth, meter);
  const Planes& first = mse[0];
  std::vector<Planes> choice;
  for (size_t k = 0; k < mse.size(); ++k)
    choice.emplace_back(first.width(), first.height(), 3, meter);
  const size_t n = first.pixels();
  for (int c = 0; c < 3; ++c)
    for (size_t i = 0; i < n; ++i) {
      size_t best = 0;
      for (size_t k = 1; k < mse.size(); ++k)
        if (mse[k].plane(c)[i] < mse[best].plane(c)[i]) best = k;
      choice[best].plane(c)[i] = 1.0f;
    }
  mse.clear();
  smooth_all(choice, smooth, meter);
  for (int c = 0; c < 3; ++c)
    for (size_t i = 0; i < n; ++i) {
      float a = 0.0f, b = 0.0f;
      for (size_t k = 0; k < candidates.size(); ++k) {
        a += choice[k].plane(c)[i] * candidates[k].a.plane(c)[i];
        b += choice[k].plane(c)[i] * candidates[k].b.plane(c)[i];
      }
      candidates[0].a.plane(c)[i] = a;
      candidates[0].b.plane(c)[i] = b;
    }
  candidates.resize(1);
}

}  // namespace anamorph::nfor
