// `whitted`: the paper's ray tracer. Hard shadows (a shadow ray crossing see-through surfaces
// scaled by their transmission, as in Whitted's paper and POV-Ray, and alpha-blended ones by
// 1 - opacity), the classic ambient term, mirror reflection and refraction with Fresnel (thin
// walls crossed straight), alpha blend's straight-on share, one sample of the area lights per hit.
#include <cmath>

#include "render/integrator.h"

namespace anamorph {

namespace {

class Whitted final : public Integrator {
 public:
  explicit Whitted(const RenderContext& ctx)
      : Integrator(ctx), see_through_(ctx.accel.has_see_through()) {
    for (const auto& m : ctx.scene.materials) {
      textured_.push_back(m->textured());
      shadow_transmission_.push_back(m->shadow_transmission());
      blends_.push_back(m->blends());
    }
  }

  Color radiance(const Ray& ray, const Hit* first, const Footprint& fp, Rng& rng,
                 uint64_t& rays) const override {
    return trace(ray, first, fp, rng, 0, 1.0, rays);
  }
  bool draws_random_numbers() const override { return ctx_.lights.has_area(); }
  bool continues_from(const Material& m) const override {
    return m.spawns_specular_rays() || m.blends();
  }

 private:
  // `weight`: the largest component of the product of the coefficients that lead to this ray.
  Color trace(const Ray& ray, const Hit* h, const Footprint& fp, Rng& rng, int depth, double weight,
              uint64_t& rays) const {
    const Lights& lights = ctx_.lights;
    const Vec3 dir = normalize(ray.d);
    if (!h) return lights.has_environment() ? lights.environment(dir) : Color{};
    const Vec3 wo = -dir;
    const Material& m = *ctx_.scene.materials[h->material];
    // (Constant textures never read their coordinates: not worth computing for them.)
    const Bsdf b = m.bsdf(textured_[h->material] ? shading_point(*h, fp) : shading_point(*h), wo);
    Color L = lights.emitted(*h, wo);
    // The classic ambient term: the environment's mean radiance on the diffuse part (its opaque
    // share), unshadowed. (Sampling it with one shadow ray per hit would only add noise to the
    // Whitted image.)
    L += b.diffuse * lights.environment_average() * b.opacity;

    if (b.has_smooth()) {
      // (A delta light's sample needs no random numbers: none are drawn for it.)
      auto add = [&](size_t li, double pmf, bool delta) {
        LightSample ls;
        const Vec2 u = delta ? Vec2{0.5, 0.5} : Vec2{rng.uniform(), rng.uniform()};
        if (!lights.sample(li, h->p, u, &ls) || !(ls.pdf > 0)) return;
        const Color f = b.eval(wo, ls.wi);
        if (max_component(f) <= 0) return;
        const double T =
            see_through_ ? transmittance(*h, ls, rays) : light_visible(ctx_, *h, ls, rays);
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

    add_specular(*h, b, wo, fp, rng, depth, weight, rays, L);
    return L;
  }

  // What the delta rays bring, each weighed as the path tracer's sampling weighs it: the mirror
  // and the dielectric's reflection and refraction (a thin wall: straight through, unrefracted),
  // all scaled by what the layers above leave (Bsdf::under_layers: the coat's and the sheen's
  // reflection is not traced, only their highlights from lights) and by the opacity, the
  // refracted light tinted (Bsdf::transmission_tint); and alpha blend's 1 - opacity straight on.
  // Added to L.
  void add_specular(const Hit& h, const Bsdf& b, const Vec3& wo, const Footprint& fp, Rng& rng,
                    int depth, double weight, uint64_t& rays, Color& L) const {
    const double keep = b.opacity * (b.has_layers() ? b.under_layers(wo) : 1.0);
    const Vec3 wr = b.frame.to_world(reflect(b.frame.to_local(wo), {0, 0, 1}));
    const double mirror = max_component(b.mirror) * keep;
    if (mirror > 0 && weight * mirror >= ctx_.bailout)
      L += b.mirror * follow(h, wr, fp, rng, depth, weight * mirror, rays) * keep;
    if (b.transmission > 0) {
      const double e = b.entering ? b.eta : 1 / b.eta;
      const double cos_i = dot(wo, b.frame.n);
      const double F = fresnel_dielectric(cos_i, e);
      const double w = weight * b.transmission * keep;
      Color t;
      if (w * F >= ctx_.bailout) t = follow(h, wr, fp, rng, depth, w * F, rays) * F;
      if (F < 1 && w * (1 - F) >= ctx_.bailout) {
        if (b.thin) {
          t += follow(h, -wo, fp, rng, depth, w * (1 - F), rays) * (1 - F) * b.transmission_tint;
        } else {
          const double sin2_t = (1 - cos_i * cos_i) / (e * e);
          const double cos_t = std::sqrt(std::max(0.0, 1 - sin2_t));
          const Vec3 wt = normalize(-wo / e + b.frame.n * (cos_i / e - cos_t));
          // (The 1 / e^2 radiance scaling cancels on leaving the medium: not part of the weight.)
          t += follow(h, wt, fp, rng, depth, w * (1 - F), rays) * ((1 - F) / (e * e)) *
               b.transmission_tint;
        }
      }
      L += t * (b.transmission * keep);
    }
    const double pass = 1 - b.opacity;
    if (pass > 0 && weight * pass >= ctx_.bailout)
      L += follow(h, -wo, fp, rng, depth, weight * pass, rays) * pass;
  }

  // The light reaching h from ls through transparent surfaces, as Whitted's paper and POV-Ray
  // shade them: each surface the shadow ray crosses scales it by its material's transmission,
  // without bending it (no caustics); an opaque surface blocks it. (The path tracer's shadow
  // rays stop at glass: its paths through glass find the light themselves.)
  // An alpha-blended one keeps 1 - opacity, and of the opaque share its transmission.
  double transmittance(const Hit& h, const LightSample& ls, uint64_t& rays) const {
    return shadow_transmittance(
        ctx_, h, ls, Accel::ShadowSet::Transmitting, rays, [&](const Hit& x) {
          const double t = shadow_transmission_[x.material];
          if (!blends_[x.material]) return t;
          const double o =
              ctx_.scene.materials[x.material]->opacity_at(texcoord_at(x, Footprint{}));
          return 1 - o + o * t;
        });
  }

  Color follow(const Hit& h, const Vec3& d, const Footprint& fp, Rng& rng, int depth, double weight,
               uint64_t& rays) const {
    const Ray r = spawn(h, d);
    Hit next;
    ++rays;
    const bool found = ctx_.accel.intersect(r, &next);
    return trace(r, found ? &next : nullptr, found ? propagate(fp, next) : Footprint{}, rng,
                 depth + 1, weight, rays);
  }

  bool see_through_ = false;                 // some object transmits: shadow rays may pass surfaces
  std::vector<uint8_t> textured_;            // per material: Material::textured()
  std::vector<double> shadow_transmission_;  // per material: Material::shadow_transmission()
  std::vector<uint8_t> blends_;              // per material: Material::blends()
};

std::unique_ptr<Integrator> create(const RenderContext& ctx) {
  return std::make_unique<Whitted>(ctx);
}

}  // namespace

extern const IntegratorFactory kWhittedIntegrator;  // (in the list of integrators.cpp)
const IntegratorFactory kWhittedIntegrator{"whitted", create};

}  // namespace anamorph
