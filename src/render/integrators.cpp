// The two radiance integrators: the paper's Whitted ray tracer and a unidirectional path tracer
// with next-event estimation and multiple importance sampling.
#include <cmath>

#include "math/sampling.h"
#include "render/integrator.h"

namespace anamorph {

namespace {

bool visible(const RenderContext& ctx, const Hit& h, const LightSample& ls, uint64_t& rays) {
  const double eps = ray_offset(h.p);
  // Stop short of the light by a relative margin: float rays may otherwise graze the emitter
  // itself near its silhouette (measured: 20% of sphere-light samples lost at 1e-6).
  const Vec3 n = dot(ls.wi, h.ng) >= 0 ? h.ng : -h.ng;
  Ray r{h.p + n * eps, ls.wi, 0, std::isinf(ls.dist) ? kInf : ls.dist * (1 - 1e-3) - eps};
  ++rays;
  return !ctx.accel.occluded(r);
}

// ---- Whitted ---------------------------------------------------------------------------------

class Whitted final : public Integrator {
 public:
  explicit Whitted(const RenderContext& ctx)
      : Integrator(ctx), see_through_(ctx.accel.has_see_through()) {
    for (const Material& m : ctx.scene.materials) textured_.push_back(m.textured());
  }

  Color radiance(const Ray& ray, const Hit* first, const Footprint& fp, Rng& rng,
                 uint64_t& rays) const override {
    return trace(ray, first, fp, rng, 0, 1.0, rays);
  }
  bool draws_random_numbers() const override { return ctx_.lights.has_area(); }

 private:
  // `weight`: the largest component of the product of the coefficients that lead to this ray.
  Color trace(const Ray& ray, const Hit* h, const Footprint& fp, Rng& rng, int depth, double weight,
              uint64_t& rays) const {
    const Lights& lights = ctx_.lights;
    const Vec3 dir = normalize(ray.d);
    if (!h) return lights.has_environment() ? lights.environment(dir) : Color{};
    const Vec3 wo = -dir;
    const Material& m = ctx_.scene.materials[h->material];
    // (Constant textures never read their coordinates: not worth computing for them.)
    const TexCoord tc = textured_[h->material] ? texcoord_at(*h, fp) : TexCoord{};
    const Bsdf b = make_bsdf(m, *h, wo, tc, nullptr);
    Color L = lights.emitted(*h, wo);
    // The classic ambient term: the environment's mean radiance on the diffuse part, unshadowed.
    // (Sampling it with one shadow ray per hit would only add noise to the Whitted image.)
    L += b.diffuse * lights.environment_average();

    if (b.has_smooth()) {
      // (A delta light's sample needs no random numbers: none are drawn for it.)
      auto add = [&](size_t li, double pmf, bool delta) {
        LightSample ls;
        const Vec2 u = delta ? Vec2{0.5, 0.5} : Vec2{rng.uniform(), rng.uniform()};
        if (!lights.sample(li, h->p, u, &ls) || !(ls.pdf > 0)) return;
        const Color f = b.eval(wo, ls.wi);
        if (max_component(f) <= 0) return;
        const double T = see_through_ ? transmittance(*h, ls, rays) : visible(ctx_, *h, ls, rays);
        if (!(T > 0)) return;
        L += f * ls.L * (T * std::abs(dot(ls.wi, b.frame.n)) / (ls.pdf * pmf));
      };
      for (uint32_t li : lights.delta_lights()) add(li, 1.0, true);
      if (lights.has_area()) {
        double pmf;
        const size_t li = lights.pick_area(rng.uniform(), &pmf);
        if (pmf > 0) add(li, pmf, false);
      }
    }
    // The tree ends at max_depth, where a branch's weight falls below the bailout (two facing
    // mirrors and glass at depth 1000 would otherwise take minutes a pixel), or on cancel.
    if (depth >= ctx_.max_depth || ctx_.cancelled()) return L;

    const Vec3 wr = b.frame.to_world(reflect(b.frame.to_local(wo), {0, 0, 1}));
    const double mirror = max_component(b.mirror);
    if (mirror > 0 && weight * mirror >= ctx_.bailout)
      L += b.mirror * follow(*h, wr, fp, rng, depth, weight * mirror, rays);
    if (b.transmission > 0) {
      const double e = b.entering ? b.eta : 1 / b.eta;
      const double cos_i = dot(wo, b.frame.n);
      const double F = fresnel_dielectric(cos_i, e);
      const double w = weight * b.transmission;
      Color t;
      if (w * F >= ctx_.bailout) t = follow(*h, wr, fp, rng, depth, w * F, rays) * F;
      if (F < 1 && w * (1 - F) >= ctx_.bailout) {
        const double sin2_t = (1 - cos_i * cos_i) / (e * e);
        const double cos_t = std::sqrt(std::max(0.0, 1 - sin2_t));
        const Vec3 wt = normalize(-wo / e + b.frame.n * (cos_i / e - cos_t));
        // (The 1 / e^2 radiance scaling cancels on leaving the medium: not part of the weight.)
        t += follow(*h, wt, fp, rng, depth, w * (1 - F), rays) * ((1 - F) / (e * e));
      }
      L += t * b.transmission;
    }
    return L;
  }

  // The light reaching h from ls through transparent surfaces, as Whitted's paper and POV-Ray
  // shade them: each surface the shadow ray crosses scales it by its material's transmission,
  // without bending it (no caustics); an opaque surface blocks it. (The path tracer's shadow
  // rays stop at glass: its paths through glass find the light themselves.) The product does
  // not depend on the order of the crossings, so an any-hit query over the opaque surfaces
  // answers most rays at once, and only those it lets through walk the see-through surfaces,
  // in a structure that holds only them.
  double transmittance(const Hit& h, const LightSample& ls, uint64_t& rays) const {
    const Vec3 n = dot(ls.wi, h.ng) >= 0 ? h.ng : -h.ng;
    Vec3 o = h.p + n * ray_offset(h.p);
    // (The light's margin as in visible(): stop short of it by a relative 1e-3.)
    const auto to_light = [&] {
      return std::isinf(ls.dist) ? kInf : (ls.dist - dot(o - h.p, ls.wi)) * (1 - 1e-3);
    };
    ++rays;
    if (!(to_light() > 0)) return 1;
    if (ctx_.accel.occluded_by_opaque(Ray{o, ls.wi, 0, to_light()})) return 0;
    double T = 1;
    for (int crossing = 0; crossing < kMaxCrossings; ++crossing) {
      const double d = to_light();
      if (!(d > 0)) return T;
      const Ray segment{o, ls.wi, 0, d};
      if (!ctx_.accel.near_see_through(segment)) return T;
      Hit x;
      if (!ctx_.accel.intersect_see_through(segment, &x)) return T;
      ++rays;  // (the segment beyond this surface)
      T *= ctx_.scene.materials[x.material].transmission;
      if (!(T > 0)) return 0;
      const Vec3 nx = dot(ls.wi, x.ng) >= 0 ? x.ng : -x.ng;
      o = x.p + nx * ray_offset(x.p);
    }
    return 0;  // (more surfaces than that: taken as opaque)
  }
  static constexpr int kMaxCrossings = 32;

  Color follow(const Hit& h, const Vec3& d, const Footprint& fp, Rng& rng, int depth, double weight,
               uint64_t& rays) const {
    const Ray r = spawn(h, d);
    Hit next;
    ++rays;
    const bool found = ctx_.accel.intersect(r, &next);
    return trace(r, found ? &next : nullptr, found ? propagate(fp, next) : Footprint{}, rng,
                 depth + 1, weight, rays);
  }

  bool see_through_ = false;       // some object transmits: shadow rays may pass surfaces
  std::vector<uint8_t> textured_;  // per material: Material::textured()
};

// ---- Path tracing ----------------------------------------------------------------------------

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
    Vec3 prev_p;
    for (int depth = 0;; ++depth) {
      const Vec3 dir = normalize(ray.d);
      if (!found) {
        if (lights.has_environment()) {
          const double w = prev_delta ? 1 : power_heuristic(prev_pdf, lights.pdf_environment(dir));
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
      const Material& m = ctx_.scene.materials[hit.material];
      const Bsdf b = make_bsdf(m, hit, wo, texcoord_at(hit, fp), nullptr);

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
        if (pmf > 0 && lights.sample(li, hit.p, u_light, &ls) && ls.pdf > 0) {
          const Color f = b.eval(wo, ls.wi);
          if (max_component(f) > 0 && visible(ctx_, hit, ls, rays)) {
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

}  // namespace

Ray Integrator::spawn(const Hit& h, const Vec3& dir) {
  const Vec3 n = dot(dir, h.ng) >= 0 ? h.ng : -h.ng;
  return Ray{h.p + n * ray_offset(h.p), dir, 0, kInf};
}

std::unique_ptr<Integrator> make_integrator(IntegratorKind kind, const RenderContext& ctx) {
  if (kind == IntegratorKind::Path) return std::make_unique<PathTracer>(ctx);
  return std::make_unique<Whitted>(ctx);
}

}  // namespace anamorph
