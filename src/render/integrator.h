// Integrators compute the radiance arriving along a camera ray. The renderer finds the first hit
// (possibly with packet tracing) and hands it over, so AOVs and integrators share one trace.
#pragma once

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <span>
#include <string_view>

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
  // Whether rays go on from a hit on `m` (and so need the pixel's footprint beyond the first
  // hit): always for the path tracer; Whitted's only from mirrors and glass.
  virtual bool continues_from(const Material& m) const {
    (void)m;
    return true;
  }

 protected:
  // A ray leaving a surface point, offset along the geometric normal to avoid self-hits.
  static Ray spawn(const Hit& h, const Vec3& dir);
  const RenderContext& ctx_;
};

// Whether a light sample's shadow ray from h reaches the light (stopping short of it by a
// relative margin).
bool light_visible(const RenderContext& ctx, const Hit& h, const LightSample& ls, uint64_t& rays);

// The light reaching h from ls through the surfaces of one shadow set (Accel::ShadowSet): each
// surface of the set the shadow ray crosses scales it by keep(hit) (in [0, 1]), without bending
// it; any other surface blocks it. The product does not depend on the order of the crossings, so
// an any-hit query over the surfaces outside the set answers most rays at once, and only those
// it lets through walk the set's surfaces, in a structure that holds only them. More than
// kMaxShadowCrossings of them: taken as opaque.
constexpr int kMaxShadowCrossings = 32;
template <class Keep>
double shadow_transmittance(const RenderContext& ctx, const Hit& h, const LightSample& ls,
                            Accel::ShadowSet set, uint64_t& rays, Keep keep) {
  const Vec3 n = dot(ls.wi, h.ng) >= 0 ? h.ng : -h.ng;
  Vec3 o = h.p + n * ray_offset(h.p);
  // (The light's margin as in light_visible(): stop short of it by a relative 1e-3.)
  const auto to_light = [&] {
    return std::isinf(ls.dist) ? kInf : (ls.dist - dot(o - h.p, ls.wi)) * (1 - 1e-3);
  };
  ++rays;
  if (!(to_light() > 0)) return 1;
  if (ctx.accel.occluded_by_opaque(Ray{o, ls.wi, 0, to_light(), h.time}, set)) return 0;
  double T = 1;
  for (int crossing = 0; crossing < kMaxShadowCrossings; ++crossing) {
    const double d = to_light();
    if (!(d > 0)) return T;
    const Ray segment{o, ls.wi, 0, d, h.time};
    if (!ctx.accel.near_see_through(segment, set)) return T;
    Hit x;
    if (!ctx.accel.intersect_see_through(segment, &x, set)) return T;
    ++rays;  // (the segment beyond this surface)
    T *= keep(x);
    if (!(T > 0)) return 0;
    const Vec3 nx = dot(ls.wi, x.ng) >= 0 ? x.ng : -x.ng;
    o = x.p + nx * ray_offset(x.p);
  }
  return 0;
}

// The integrators by name (render.integrator): each one's file defines its class and its entry,
// the one list is in integrators.cpp. (The AOV views are not integrators: the renderer shows
// them, RenderSettings::view.) The scene reader declares the same names (scene_schema.cpp,
// declared_integrators()); tests/render/integrator_test.cpp holds the two lists equal.
struct IntegratorFactory {
  std::string_view name;
  std::unique_ptr<Integrator> (*create)(const RenderContext& ctx);
};
std::span<const IntegratorFactory* const> integrator_factories();
// Throws std::invalid_argument naming the valid names for a name not in the list.
std::unique_ptr<Integrator> make_integrator(std::string_view name, const RenderContext& ctx);

}  // namespace anamorph
