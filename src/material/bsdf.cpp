#include "material/bsdf.h"

#include <algorithm>
#include <cmath>

#include "math/sampling.h"

namespace anamorph {

double fresnel_dielectric(double cos_i, double eta) {
  cos_i = std::clamp(cos_i, -1.0, 1.0);
  if (cos_i < 0) {
    eta = 1 / eta;
    cos_i = -cos_i;
  }
  const double sin2_t = (1 - cos_i * cos_i) / (eta * eta);
  if (sin2_t >= 1) return 1;  // total internal reflection
  const double cos_t = std::sqrt(1 - sin2_t);
  const double rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  const double rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  return 0.5 * (rs * rs + rp * rp);
}

Color fresnel_schlick(const Color& f0, double c) {
  const double m = std::pow(std::clamp(1 - c, 0.0, 1.0), 5);
  return f0 + (Color(1) - f0) * m;
}

double ggx_d(double cos_h, double a) {
  const double a2 = a * a;
  const double d = cos_h * cos_h * (a2 - 1) + 1;
  return a2 / (kPi * d * d);
}
double smith_g1(double cos_v, double a) {
  const double a2 = a * a;
  const double c2 = cos_v * cos_v;
  return 2 * cos_v / (cos_v + std::sqrt(a2 + (1 - a2) * c2));
}

Vec3 sample_ggx_visible(const Vec3& wo, double a, Vec2 u) {
  // The view stretched to the unit-roughness configuration, where visible normals are the
  // sum of the view and a point uniform on the cap of the sphere z > -view.z.
  const Vec3 v = normalize(Vec3{wo.x * a, wo.y * a, wo.z});
  double sp, cp;
  sincos_poly(2 * kPi * u.x, &sp, &cp);
  const double z = (1 - u.y) * (1 + v.z) - v.z;
  const double r = std::sqrt(std::clamp(1 - z * z, 0.0, 1.0));
  const Vec3 hs = Vec3{r * cp, r * sp, z} + v;
  const Vec3 h = normalize(Vec3{hs.x * a, hs.y * a, std::max(hs.z, 0.0)});
  return h * (2 * dot(wo, h)) - wo;
}

double ggx_visible_pdf(const Vec3& wo, const Vec3& wi, double a) {
  const Vec3 h = normalize(wo + wi);
  return smith_g1(wo.z, a) * ggx_d(h.z, a) / (4 * wo.z);
}

namespace {

// Lobe selection probabilities from rough albedo estimates.
struct LobeWeights {
  double diffuse, phong, ggx, mirror, dielectric, coat, sheen, total;
};
LobeWeights lobe_weights(const Bsdf& b, const Vec3& wo_w) {
  LobeWeights w{luminance(b.diffuse),
                luminance(b.phong),
                luminance(b.ggx_f0) > 0 ? std::max(0.1, luminance(b.ggx_f0)) : 0.0,
                luminance(b.mirror),
                b.transmission,
                0,
                0,
                0};
  w.total = w.diffuse + w.phong + w.ggx + w.mirror + w.dielectric;
  if (b.has_layers()) {
    // (The lobes below in proportion to what the layers leave them.)
    const double below = b.under_layers(wo_w);
    w.diffuse *= below, w.phong *= below, w.ggx *= below, w.mirror *= below;
    w.dielectric *= below;
    w.coat = b.coat_choice(wo_w);
    w.sheen = b.sheen_choice();
    w.total = w.diffuse + w.phong + w.ggx + w.mirror + w.dielectric + w.coat + w.sheen;
  }
  return w;
}

}  // namespace

Color Bsdf::eval(const Vec3& wo_w, const Vec3& wi_w) const {
  const Vec3 wo = frame.to_local(wo_w), wi = frame.to_local(wi_w);
  // Reflection only, and only when both directions are on the geometric outside as well, which
  // avoids light leaking through shading-normal mismatches.
  if (wo.z <= 0 || wi.z <= 0 || dot(wi_w, ng) <= 0) return {};
  Color f = diffuse * (kInvPi * opacity);
  if (max_component(phong) > 0) {
    const Vec3 r{-wo.x, -wo.y, wo.z};
    const double c = std::max(0.0, dot(r, wi));
    f += phong * ((phong_exponent + 2) / (2 * kPi) * std::pow(c, phong_exponent) * opacity);
  }
  if (max_component(ggx_f0) > 0) {
    const Vec3 h = normalize(wo + wi);
    const double d = ggx_d(h.z, ggx_alpha);
    const double g = smith_g1(wo.z, ggx_alpha) * smith_g1(wi.z, ggx_alpha);
    f += fresnel_schlick(ggx_f0, dot(wi, h)) * (d * g / (4 * wo.z * wi.z) * opacity);
  }
  return has_layers() ? layered(wo_w, wi_w, f) : f;
}

double Bsdf::pdf(const Vec3& wo_w, const Vec3& wi_w) const {
  const Vec3 wo = frame.to_local(wo_w), wi = frame.to_local(wi_w);
  if (wo.z <= 0 || wi.z <= 0) return 0;
  const LobeWeights w = lobe_weights(*this, wo_w);
  if (w.total <= 0) return 0;
  double p = w.diffuse * cosine_hemisphere_pdf(wi.z);
  if (w.phong > 0) {
    const Vec3 r{-wo.x, -wo.y, wo.z};
    const double c = std::max(0.0, dot(r, wi));
    p += w.phong * (phong_exponent + 1) / (2 * kPi) * std::pow(c, phong_exponent);
  }
  if (w.ggx > 0) p += w.ggx * ggx_visible_pdf(wo, wi, ggx_alpha);
  if (w.coat + w.sheen > 0) p += layers_pdf(wo_w, wi_w, w.coat, w.sheen);
  return p / w.total * opacity;
}

namespace {

// Alpha blend: straight on, with probability 1 - opacity and weight 1.
void sample_pass_through(const Bsdf& b, const Vec3& wo_w, BsdfSample* out) {
  out->wi = -wo_w;
  out->delta = true;
  out->pass_through = true;
  out->pdf = 1 - b.opacity;
  out->f = Color(1 - b.opacity);
  out->weight = Color(1);
}

// The dielectric's delta lobes, chosen with probability `sel`: reflect with probability F (`v`
// below it), else refract, or go straight through a thin wall; `below` is what the layers leave.
void sample_dielectric(const Bsdf& b, const Vec3& wo, const Vec3& wo_w, double v, double sel,
                       double below, BsdfSample* out) {
  const double e = b.entering ? b.eta : 1 / b.eta;
  const double fr = fresnel_dielectric(wo.z, e);
  out->delta = true;
  if (v < fr) {
    out->wi = b.frame.to_world({-wo.x, -wo.y, wo.z});
    out->pdf = sel * fr;
    out->weight = Color(b.transmission * below / sel);
  } else if (b.thin) {
    // A thin wall: the two refractions cancel; the light goes on as it came.
    out->wi = -wo_w;
    out->pdf = sel * (1 - fr);
    out->weight = Color(b.transmission * below / sel) * b.transmission_tint;
  } else {
    const double sin2_t = (1 - wo.z * wo.z) / (e * e);
    const double cos_t = std::sqrt(std::max(0.0, 1 - sin2_t));
    const Vec3 wt = Vec3{-wo.x / e, -wo.y / e, -cos_t};
    out->wi = b.frame.to_world(normalize(wt));
    out->pdf = sel * (1 - fr);
    // Radiance is scaled by 1/eta^2 crossing into the denser medium (non-symmetric BTDF).
    out->weight = Color(b.transmission * below / sel / (e * e)) * b.transmission_tint;
    out->eta_scale = e * e;
  }
  out->f = out->weight * b.opacity;
  out->pdf *= b.opacity;
}

// A direction (local frame) from the lobes that are not deltas, `x` (past the delta lobes'
// weights) choosing among them: diffuse, Phong, GGX, then the coat and the sheen.
bool sample_smooth_lobes(const Bsdf& b, const LobeWeights& w, const Vec3& wo, const Vec3& wo_w,
                         double x, Vec2 u, Vec3* wi) {
  const double x_layers = x - (w.diffuse + w.phong + w.ggx);
  if (w.coat + w.sheen > 0 && x_layers >= 0) {
    // The layers: the coat's GGX, or the sheen's cosine-weighted hemisphere.
    Vec3 wi_w;
    if (x_layers < w.coat) {
      if (!b.sample_coat(wo_w, u, &wi_w)) return false;
    } else {
      wi_w = b.frame.to_world(sample_cosine_hemisphere(u));
    }
    *wi = b.frame.to_local(wi_w);
  } else if (x < w.diffuse) {
    *wi = sample_cosine_hemisphere(u);
  } else if (x < w.diffuse + w.phong) {
    // cos^n lobe around the mirror direction.
    const double cos_a = std::pow(u.x, 1 / (b.phong_exponent + 1));
    const double sin_a = std::sqrt(std::max(0.0, 1 - cos_a * cos_a));
    double sp, cp;
    sincos_poly(2 * kPi * u.y, &sp, &cp);
    const Frame rf = Frame::from_normal({-wo.x, -wo.y, wo.z});
    *wi = rf.to_world({sin_a * cp, sin_a * sp, cos_a});
  } else {
    *wi = sample_ggx_visible(wo, b.ggx_alpha, u);  // (its visible normals)
  }
  return true;
}

}  // namespace

bool Bsdf::sample(const Vec3& wo_w, Vec2 u, double u3, BsdfSample* out) const {
  const Vec3 wo = frame.to_local(wo_w);
  if (wo.z <= 0) return false;
  if (opacity < 1) {
    // Alpha blend: straight on with probability 1 - opacity (its weight 1), else the lobes, whose
    // f and pdf both carry the opacity (their weight does not).
    if (u3 < 1 - opacity) {
      sample_pass_through(*this, wo_w, out);
      return true;
    }
    u3 = std::min((u3 - (1 - opacity)) / opacity, std::nextafter(1.0, 0.0));
  }
  const LobeWeights w = lobe_weights(*this, wo_w);
  if (w.total <= 0) return false;
  double x = u3 * w.total;
  // The delta lobes below the layers keep what the layers leave them.
  const double below = has_layers() ? under_layers(wo_w) : 1;
  // Delta lobes first: their choice probability enters the weight.
  if (x < w.mirror) {
    out->wi = frame.to_world({-wo.x, -wo.y, wo.z});
    out->delta = true;
    out->pdf = w.mirror / w.total;
    out->weight = mirror * below / out->pdf;
    out->f = mirror * (below * opacity);
    out->pdf *= opacity;
    return true;
  }
  x -= w.mirror;
  if (x < w.dielectric) {
    // (the random number split again: reflect with probability F)
    sample_dielectric(*this, wo, wo_w, x / w.dielectric, w.dielectric / w.total, below, out);
    return true;
  }
  x -= w.dielectric;
  Vec3 wi;
  if (!sample_smooth_lobes(*this, w, wo, wo_w, x, u, &wi) || wi.z <= 0) return false;
  out->wi = frame.to_world(wi);
  out->delta = false;
  if (w.total == w.diffuse) {
    // Lambert alone (most surfaces): pdf and eval without going back to the local frame.
    out->pdf = cosine_hemisphere_pdf(wi.z);
    if (!(out->pdf > 0)) return false;
    out->f = dot(out->wi, ng) > 0 ? diffuse * kInvPi : Color{};
    out->weight = out->f * (wi.z / out->pdf);
    out->f = out->f * opacity;
    out->pdf *= opacity;
    return true;
  }
  out->pdf = pdf(wo_w, out->wi);
  if (!(out->pdf > 0)) return false;
  out->f = eval(wo_w, out->wi);
  out->weight = out->f * (std::abs(wi.z) / out->pdf);
  return true;
}

}  // namespace anamorph
