// The one list of integrators (adding one = its file, and its line in kIntegrators below), and
// what they share.
#include <fmt/format.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "render/integrator.h"

namespace anamorph {

extern const IntegratorFactory kWhittedIntegrator;  // whitted_integrator.cpp
extern const IntegratorFactory kPathIntegrator;     // path_integrator.cpp

namespace {

const IntegratorFactory* const kIntegrators[] = {&kWhittedIntegrator, &kPathIntegrator};

}  // namespace

std::span<const IntegratorFactory* const> integrator_factories() { return kIntegrators; }

std::unique_ptr<Integrator> make_integrator(std::string_view name, const RenderContext& ctx) {
  std::string valid;
  for (const IntegratorFactory* f : kIntegrators) {
    if (f->name == name) return f->create(ctx);
    valid += (valid.empty() ? "" : ", ") + std::string(f->name);
  }
  throw std::invalid_argument(fmt::format("unknown integrator \"{}\" (valid: {})", name, valid));
}

bool light_visible(const RenderContext& ctx, const Hit& h, const LightSample& ls, uint64_t& rays) {
  const double eps = ray_offset(h.p);
  // Stop short of the light by a relative margin: float rays may otherwise graze the emitter
  // itself near its silhouette (measured: 20% of sphere-light samples lost at 1e-6).
  const Vec3 n = dot(ls.wi, h.ng) >= 0 ? h.ng : -h.ng;
  Ray r{h.p + n * eps, ls.wi, 0, std::isinf(ls.dist) ? kInf : ls.dist * (1 - 1e-3) - eps, h.time};
  ++rays;
  return !ctx.accel.occluded(r);
}

Ray Integrator::spawn(const Hit& h, const Vec3& dir) {
  const Vec3 n = dot(dir, h.ng) >= 0 ? h.ng : -h.ng;
  return Ray{h.p + n * ray_offset(h.p), dir, 0, kInf, h.time};
}

}  // namespace anamorph
