// Integrators compute the radiance arriving along a camera ray. The renderer finds the first hit
// (possibly with packet tracing) and hands it over, so AOVs and integrators share one trace.
#pragma once

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <string>

#include "accel/accel.h"
#include "math/rng.h"
#include "render/lights.h"
#include "render/shading.h"
#include "scene/scene.h"

namespace anamorph {

struct RenderContext {
  const Scene& scene;
  const Accel& accel;
  const Lights& lights;
  int max_depth;
  double bailout = 0;                         // Whitted's ray-weight cut-off (RenderSettings)
  const std::atomic<bool>* cancel = nullptr;  // set: integrators stop tracing and return black
  bool cancelled() const { return cancel && cancel->load(std::memory_order_relaxed); }
};

// How far a ray leaving a surface point starts off it (along the normal), against float
// self-intersection in Embree: relative to the point's distance from the origin.
inline double ray_offset(const Vec3& p) {
  return 1e-5 * (1 + std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}));
}

class Integrator {
 public:
  explicit Integrator(const RenderContext& ctx) : ctx_(ctx) {}
  virtual ~Integrator() = default;
  // `first` is the first hit of `ray` or null for a miss; `fp` its pixel footprint. Rays traced
  // beyond the primary one are added to `rays`.
  virtual Color radiance(const Ray& ray, const Hit* first, const Footprint& fp, Rng& rng,
                         uint64_t& rays) const = 0;
  // Whether radiance() draws from `rng` at all: when it does not (Whitted lit by point and
  // spot lights alone), a pixel-center render seeds no generator.
  virtual bool draws_random_numbers() const { return true; }

 protected:
  // A ray leaving a surface point, offset along the geometric normal to avoid self-hits.
  static Ray spawn(const Hit& h, const Vec3& dir);
  const RenderContext& ctx_;
};

// Whitted or Path; AOV integrators are handled by the renderer.
std::unique_ptr<Integrator> make_integrator(IntegratorKind kind, const RenderContext& ctx);

}  // namespace anamorph
