// `path`: unidirectional path tracing with next-event estimation, multiple importance sampling
// and Russian roulette. Absorption inside solids (Bsdf::sigma_a) along the segments between
// entering and leaving them. Alpha-blended surfaces are transparent to shadow rays too (each
// crossing keeps 1 - opacity of the light); a path going straight through one keeps the MIS
// state of the vertex before it, whose light the shadow ray through it also estimates.
#include <cmath>

#include "math/sampling.h"
#include "render/integrator.h"

namespace anamorph {

namespace {

class PathTracer final : public Integrator {
 public:
  explicit PathTracer(const RenderContext& ctx)
      : Integrator(ctx), blended_(ctx.accel.has_see_through(Accel::ShadowSet::Blended)) {}

  Color radiance(const Ray& ray0, const Hit* first, const Footprint& fp0, Rng& rng,
                 uint64_t& rays) const override {
    Color L, beta(1.0);
    double eta_scale = 1;  // product of eta^2 over the refractions so far (see survives_roulette)
    Ray ray = ray0;
    Hit hit;
    bool found = first != nullptr;
    if (found) hit = *first;
    Footprint fp = fp0;
    Scattered prev;
    for (int depth = 0;; ++depth) {
      const Vec3 dir = normalize(ray.d);
      if (!found) {
        add_environment(dir, beta, prev, L);
        break;
      }
      const Vec3 wo = -dir;
      add_emission(hit, dir, beta, prev, L);
      if (depth >= ctx_.max_depth || ctx_.cancelled()) break;
      const Material& m = *ctx_.scene.materials[hit.material];
      const Bsdf b = m.bsdf(shading_point(hit, fp), wo);
      absorb(b, hit, ray, beta);

      // This bounce's numbers, drawn up front so that 2D samples stay paired (with a QMC stream,
      // stratified across the pixel's samples): light position, BSDF direction, light choice
      // and BSDF lobe.
      Vec2 u_light, u_bsdf;
      rng.uniform2(u_light.x, u_light.y);
      rng.uniform2(u_bsdf.x, u_bsdf.y);
      const double u_pick = rng.uniform(), u_lobe = rng.uniform();

      L += direct(hit, b, wo, beta, u_light, u_pick, rays);

      BsdfSample s;
      if (!b.sample(wo, u_bsdf, u_lobe, &s)) break;
      beta *= s.weight;
      eta_scale *= s.eta_scale;
      if (!s.pass_through) prev = {s.pdf, s.delta, hit.p, b.frame.n};
      if (!survives_roulette(depth, rng, eta_scale, beta)) break;
      ray = spawn(hit, s.wi);
      ++rays;
      found = ctx_.accel.intersect(ray, &hit);
      // Specular bounces keep the ray cone (sharp reflections of textures stay filtered); after a
      // rough bounce the path's own sampling does the filtering.
      fp = found && s.delta ? propagate(fp, hit) : Footprint{};
    }
    return L;
  }

 private:
  // The vertex a path last scattered at (pass-throughs keep the one before them): its sampling
  // pdf, whether it was a delta lobe (then no MIS weight), its point and shading normal.
  struct Scattered {
    double pdf = 0;
    bool delta = true;
    Vec3 p, n;
  };

  // What the environment adds where the path leaves the scene in direction dir, weighted by MIS
  // against the light sampling at the vertex before.
  void add_environment(const Vec3& dir, const Color& beta, const Scattered& prev, Color& L) const {
    const Lights& lights = ctx_.lights;
    if (!lights.has_environment()) return;
    const double w =
        prev.delta ? 1 : power_heuristic(prev.pdf, lights.pdf_environment(dir, prev.p, prev.n));
    L += beta * lights.environment(dir) * w;
  }

  // What an emitter hit by the path (arriving in direction dir) adds, weighted likewise.
  void add_emission(const Hit& hit, const Vec3& dir, const Color& beta, const Scattered& prev,
                    Color& L) const {
    const Lights& lights = ctx_.lights;
    const Color le = lights.emitted(hit, -dir);
    if (!(max_component(le) > 0)) return;
    const double w =
        prev.delta ? 1 : power_heuristic(prev.pdf, lights.pdf_emitter(hit, prev.p, prev.n, dir));
    L += beta * le * w;
  }

  // Russian roulette from the fourth scattering event with pbrt-v4's rule (Pharr, Jakob &
  // Humphreys, 4th ed., 13.4.2): a path whose throughput, with the radiance scaling of its
  // refractions undone (eta_scale), is still >= 1 in some channel always goes on (white walls and
  // glass never end it); otherwise it ends with probability 1 - that maximum and survivors carry
  // what the ended ones would have. (Starting at the second event, as pbrt-v4 does, measured
  // worse: bench/cycles box +28..+88 % RMSE at equal samples, docs/performance.md.) The number is
  // drawn at every bounce from the fourth, used or not, so a pixel's QMC dimensions do not depend
  // on the path's throughput. Also ends dark paths.
  static bool survives_roulette(int depth, Rng& rng, double eta_scale, Color& beta) {
    if (depth >= 3) {
      const double u = rng.uniform();
      const double keep = max_component(beta) * eta_scale;
      if (keep < 1) {
        if (u < 1 - keep) return false;  // (as before for keep < 0.95: the same paths end)
        beta /= keep;
      }
    }
    return !(max_component(beta) <= 0);  // (a NaN path goes on, as it always did)
  }

  // Next-event estimation: the light of one picked light source reaching `hit` unoccluded,
  // times the path's throughput, weighted against the BSDF's sampling of the same direction.
  Color direct(const Hit& hit, const Bsdf& b, const Vec3& wo, const Color& beta, Vec2 u_light,
               double u_pick, uint64_t& rays) const {
    const Lights& lights = ctx_.lights;
    if (!b.has_smooth() || lights.count() == 0) return Color();
    double pmf;
    size_t li;
    LightSample ls;
    if (!(lights.pick(u_pick, hit.p, b.frame.n, &li, &pmf) && pmf > 0 &&
          lights.sample(li, hit.p, b.frame.n, u_light, &ls) && ls.pdf > 0))
      return Color();
    const Color f = b.eval(wo, ls.wi);
    if (!(max_component(f) > 0)) return Color();
    const double T = blended_ ? transmittance(hit, ls, rays) : light_visible(ctx_, hit, ls, rays);
    if (!(T > 0)) return Color();
    const double lpdf = ls.pdf * pmf;
    const double w = ls.delta ? 1 : power_heuristic(lpdf, b.pdf(wo, ls.wi));
    return beta * f * ls.L * (T * std::abs(dot(ls.wi, b.frame.n)) * w / lpdf);
  }

  // The light reaching hit from ls through alpha-blended surfaces: each keeps 1 - its opacity at
  // the crossing (texture read unfiltered); any other surface blocks it.
  double transmittance(const Hit& hit, const LightSample& ls, uint64_t& rays) const {
    return shadow_transmittance(ctx_, hit, ls, Accel::ShadowSet::Blended, rays, [&](const Hit& x) {
      return 1 - ctx_.scene.materials[x.material]->opacity_at(texcoord_at(x, Footprint{}));
    });
  }

  // Leaving an absorbing solid at `hit`: the segment inside is attenuated (Beer-Lambert).
  static void absorb(const Bsdf& b, const Hit& hit, const Ray& ray, Color& beta) {
    if (b.entering || !(max_component(b.sigma_a) > 0)) return;
    const double d = hit.t * length(ray.d);
    for (int c = 0; c < 3; ++c) beta[c] *= std::exp(-b.sigma_a[c] * d);
  }

  bool blended_;  // the scene has alpha-blended surfaces: shadow rays pass them
};

std::unique_ptr<Integrator> create(const RenderContext& ctx) {
  return std::make_unique<PathTracer>(ctx);
}

}  // namespace

extern const IntegratorFactory kPathIntegrator;  // (in the list of integrators.cpp)
const IntegratorFactory kPathIntegrator{"path", create};

}  // namespace anamorph
