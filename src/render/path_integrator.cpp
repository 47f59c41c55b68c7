// `path`: unidirectional path tracing with next-event estimation, multiple importance sampling
// and Russian roulette. Absorption inside solids (Bsdf::sigma_a) along the segments between
// entering and leaving them.
#include <cmath>

#include "math/sampling.h"
#include "render/integrator.h"

namespace anamorph {

namespace {

class PathTracer final : public Integrator {
 public:
  using Integrator::Integrator;

  Color radiance(const Ray& ray0, const Hit* first, const Footprint& fp0, Rng& rng,
                 uint64_t& rays) const override {
    const Lights& lights = ctx_.lights;
    Color L, beta(1.0);
    Ray ray = ray0;
    Hit hit;
    bool found = first != nullptr;
    if (found) hit = *first;
    Footprint fp = fp0;
    double prev_pdf = 0;
    bool prev_delta = true;
    Vec3 prev_p, prev_n;  // the point the ray left and its shading normal
    for (int depth = 0;; ++depth) {
      const Vec3 dir = normalize(ray.d);
      if (!found) {
        if (lights.has_environment()) {
          const double w =
              prev_delta ? 1 : power_heuristic(prev_pdf, lights.pdf_environment(dir, prev_n));
          L += beta * lights.environment(dir) * w;
        }
        break;
      }
      const Vec3 wo = -dir;
      const Color le = lights.emitted(hit, wo);
      if (max_component(le) > 0) {
        const double w =
            prev_delta ? 1 : power_heuristic(prev_pdf, lights.pdf_emitter(hit, prev_p, dir));
        L += beta * le * w;
      }
      if (depth >= ctx_.max_depth || ctx_.cancelled()) break;
      const Material& m = *ctx_.scene.materials[hit.material];
      const Bsdf b = m.bsdf(shading_point(hit, fp), wo);
      // Leaving an absorbing solid: the segment inside was attenuated (Beer-Lambert).
      if (!b.entering && max_component(b.sigma_a) > 0) {
        const double d = hit.t * length(ray.d);
        for (int c = 0; c < 3; ++c) beta[c] *= std::exp(-b.sigma_a[c] * d);
      }

      // This bounce's numbers, drawn up front so that 2D samples stay paired (with a QMC stream,
      // stratified across the pixel's samples): light position, BSDF direction, light choice
      // and BSDF lobe.
      Vec2 u_light, u_bsdf;
      rng.uniform2(u_light.x, u_light.y);
      rng.uniform2(u_bsdf.x, u_bsdf.y);
      const double u_pick = rng.uniform(), u_lobe = rng.uniform();

      // Next-event estimation.
      if (b.has_smooth() && lights.count() > 0) {
        double pmf;
        const size_t li = lights.pick(u_pick, &pmf);
        LightSample ls;
        if (pmf > 0 && lights.sample(li, hit.p, b.frame.n, u_light, &ls) && ls.pdf > 0) {
          const Color f = b.eval(wo, ls.wi);
          if (max_component(f) > 0 && light_visible(ctx_, hit, ls, rays)) {
            const double lpdf = ls.pdf * pmf;
            const double w = ls.delta ? 1 : power_heuristic(lpdf, b.pdf(wo, ls.wi));
            L += beta * f * ls.L * (std::abs(dot(ls.wi, b.frame.n)) * w / lpdf);
          }
        }
      }

      BsdfSample s;
      if (!b.sample(wo, u_bsdf, u_lobe, &s)) break;
      beta *= s.weight;
      prev_pdf = s.pdf;
      prev_delta = s.delta;
      prev_p = hit.p;
      prev_n = b.frame.n;
      if (depth >= 3) {
        const double q = std::max(0.05, 1 - max_component(beta));
        if (rng.uniform() < q) break;
        beta /= 1 - q;
      }
      if (max_component(beta) <= 0) break;
      ray = spawn(hit, s.wi);
      ++rays;
      found = ctx_.accel.intersect(ray, &hit);
      // Specular bounces keep the ray cone (sharp reflections of textures stay filtered); after a
      // rough bounce the path's own sampling does the filtering.
      fp = found && s.delta ? propagate(fp, hit) : Footprint{};
    }
    return L;
  }
};

std::unique_ptr<Integrator> create(const RenderContext& ctx) {
  return std::make_unique<PathTracer>(ctx);
}

}  // namespace

extern const IntegratorFactory kPathIntegrator;  // (in the list of integrators.cpp)
const IntegratorFactory kPathIntegrator{"path", create};

}  // namespace anamorph
