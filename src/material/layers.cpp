// The BSDF's layers over its other lobes (bsdf.h): glTF's KHR_materials_clearcoat and
// KHR_materials_sheen, layered as the glTF specification writes them:
//   f = coat + (1 - coat F_c(wo)) (sheen + s(wo, wi) below)
// F_c Schlick's Fresnel of a dielectric of IOR 1.5 (F0 = 0.04) at the coat's normal,
// s = min(1 - max(sheen) E(wo), 1 - max(sheen) E(wi)) and E the sheen lobe's directional albedo.
// The coat takes from below exactly what it reflects at normal-to-wo incidence (F_c(wo)), so a
// coated white furnace stays below 1; the sheen's scaling is the specification's.
#include <algorithm>
#include <array>
#include <cmath>

#include "material/bsdf.h"
#include "math/sampling.h"

namespace anamorph {

namespace {

constexpr double kCoatF0 = 0.04;
// Sheen roughness below this makes Charlie's distribution a sliver at grazing half-vectors that
// neither the albedo table nor sampling resolve (the Khronos sample viewer clamps likewise).
constexpr double kMinSheenRoughness = 0.07;

double schlick(double f0, double c) {
  const double m = std::pow(std::clamp(1 - c, 0.0, 1.0), 5);
  return f0 + (1 - f0) * m;
}

// Charlie's sheen distribution (Estevez & Kulla 2017), alpha = roughness^2.
double charlie_d(double cos_h, double roughness) {
  const double r = std::max(roughness, kMinSheenRoughness);
  const double inv = 1 / (r * r);
  const double sin2 = std::max(0.0, 1 - cos_h * cos_h);
  return (2 + inv) * std::pow(sin2, 0.5 * inv) / (2 * kPi);
}

// Neubelt & Pettineo's visibility (2013), the sheen's V = G / (4 cos_o cos_i).
double neubelt_v(double cos_o, double cos_i) { return 1 / (4 * (cos_i + cos_o - cos_i * cos_o)); }

double sheen_lobe(double cos_o, const Vec3& wi, const Vec3& h, double roughness) {
  return charlie_d(h.z, roughness) * neubelt_v(cos_o, wi.z);
}

// E(mu, r) on a 24 x 24 grid (mu = cos theta_o, r = sheen roughness, both 0..1), integrated
// over the hemisphere of wi by the midpoint rule (48 x 48 in theta, phi; symmetric in phi).
constexpr int kTable = 24, kQuad = 48;
using AlbedoTable = std::array<double, kTable * kTable>;

AlbedoTable make_albedo_table() {
  AlbedoTable t{};
  const double dt = 0.5 * kPi / kQuad, dp = kPi / kQuad;
  for (int i = 0; i < kTable; ++i) {
    const double mu = std::max(double(i) / (kTable - 1), 1e-3);
    const Vec3 wo{std::sqrt(1 - mu * mu), 0, mu};
    for (int j = 0; j < kTable; ++j) {
      const double r = double(j) / (kTable - 1);
      double sum = 0;
      for (int a = 0; a < kQuad; ++a) {
        const double th = (a + 0.5) * dt, st = std::sin(th), ct = std::cos(th);
        for (int b = 0; b < kQuad; ++b) {
          const double ph = (b + 0.5) * dp;
          const Vec3 wi{st * std::cos(ph), st * std::sin(ph), ct};
          sum += sheen_lobe(mu, wi, normalize(wo + wi), r) * ct * st;
        }
      }
      t[size_t(i * kTable + j)] = std::min(1.0, 2 * sum * dt * dp);
    }
  }
  return t;
}

}  // namespace

double sheen_albedo(double cos_theta, double roughness) {
  static const AlbedoTable table = make_albedo_table();
  const double x = std::clamp(cos_theta, 0.0, 1.0) * (kTable - 1);
  const double y = std::clamp(roughness, 0.0, 1.0) * (kTable - 1);
  const int i = std::min(int(x), kTable - 2), j = std::min(int(y), kTable - 2);
  const double fx = x - i, fy = y - j;
  const auto at = [&](int a, int b) { return table[size_t(a * kTable + b)]; };
  return (at(i, j) * (1 - fy) + at(i, j + 1) * fy) * (1 - fx) +
         (at(i + 1, j) * (1 - fy) + at(i + 1, j + 1) * fy) * fx;
}

Color Bsdf::layered(const Vec3& wo_w, const Vec3& wi_w, const Color& below) const {
  const Vec3 wo = frame.to_local(wo_w), wi = frame.to_local(wi_w);
  Color f = below;
  const double s = max_component(sheen);
  if (s > 0) {
    const double scale = std::min(1 - s * sheen_albedo(wo.z, sheen_roughness),
                                  1 - s * sheen_albedo(wi.z, sheen_roughness));
    f = f * scale + sheen * (sheen_lobe(wo.z, wi, normalize(wo + wi), sheen_roughness) * opacity);
  }
  if (coat > 0) {
    const Vec3 co = coat_frame.to_local(wo_w), ci = coat_frame.to_local(wi_w);
    f = f * (1 - coat * schlick(kCoatF0, std::max(co.z, 0.0)));
    if (co.z > 0 && ci.z > 0) {
      const Vec3 h = normalize(co + ci);
      const double g = smith_g1(co.z, coat_alpha) * smith_g1(ci.z, coat_alpha);
      f += Color(coat * schlick(kCoatF0, dot(ci, h)) * ggx_d(h.z, coat_alpha) * g /
                 (4 * co.z * ci.z) * opacity);
    }
  }
  return f;
}

double Bsdf::under_layers(const Vec3& wo_w) const {
  double k = 1;
  const double s = max_component(sheen);
  if (s > 0) k *= 1 - s * sheen_albedo(dot(wo_w, frame.n), sheen_roughness);
  if (coat > 0) k *= 1 - coat * schlick(kCoatF0, std::max(dot(wo_w, coat_frame.n), 0.0));
  return std::max(k, 0.0);
}

double Bsdf::coat_choice(const Vec3& wo_w) const {
  if (!(coat > 0)) return 0;
  return coat * std::max(0.1, schlick(kCoatF0, std::max(dot(wo_w, coat_frame.n), 0.0)));
}

double Bsdf::sheen_choice() const { return 0.5 * max_component(sheen); }

double Bsdf::layers_pdf(const Vec3& wo_w, const Vec3& wi_w, double w_coat, double w_sheen) const {
  double p = 0;
  if (w_coat > 0) {
    const Vec3 co = coat_frame.to_local(wo_w), ci = coat_frame.to_local(wi_w);
    if (co.z > 0 && ci.z > 0) p += w_coat * ggx_visible_pdf(co, ci, coat_alpha);
  }
  if (w_sheen > 0) p += w_sheen * cosine_hemisphere_pdf(std::max(dot(wi_w, frame.n), 0.0));
  return p;
}

bool Bsdf::sample_coat(const Vec3& wo_w, Vec2 u, Vec3* wi_w) const {
  const Vec3 wo = coat_frame.to_local(wo_w);
  if (wo.z <= 0) return false;
  const Vec3 wi = sample_ggx_visible(wo, coat_alpha, u);
  if (wi.z <= 0) return false;
  *wi_w = coat_frame.to_world(wi);
  return true;
}

}  // namespace anamorph
