#include "render/lights.h"

#include <algorithm>
#include <cmath>

#include "math/frame.h"
#include "math/sampling.h"

namespace anamorph {

namespace {
double triangle_area(const Vec3& a, const Vec3& b, const Vec3& c) {
  return 0.5 * length(cross(b - a, c - a));
}

// What an environment image is sampled by, texel by texel: the largest luminance its bilinear
// lookup (Lights::environment) takes anywhere in the texel, times the largest sin theta of the
// texel's row. Both are bounds, so radiance / pdf never exceeds 2 pi^2 times their mean. With the
// texel's own luminance (as before) the half-texel ring that the lookup blurs around a small
// bright sun was sampled as sky: a 4 x 3-texel sun of 3000 on a sky of 0.5 gave a ring direction
// 1700 times the weight of a sun direction (fireflies that did not average out). The bilinear
// value in a texel's quarter lies between its corners: the texel's centre, the midpoints towards
// its 4 neighbours and the centres of the 4 blocks of 2 x 2 around its corners.
std::vector<double> environment_sampling_weights(const Image& im) {
  const int w = im.width, h = im.height;
  auto lum = [&](int x, int y) {
    x = ((x % w) + w) % w;  // wraps in u, clamps in v, as the lookup
    y = std::clamp(y, 0, h - 1);
    return luminance(Color{im.at(x, y, 0), im.at(x, y, 1), im.at(x, y, 2)});
  };
  std::vector<double> f(size_t(w) * h);
  for (int y = 0; y < h; ++y) {
    const double t0 = kPi * y / h, t1 = kPi * (y + 1) / h;
    const double sin_max =
        t0 <= kPi / 2 && t1 >= kPi / 2 ? 1.0 : std::max(std::sin(t0), std::sin(t1));
    for (int x = 0; x < w; ++x) {
      const double c = lum(x, y);
      double m = c;
      for (int dy = -1; dy <= 1; dy += 2)
        for (int dx = -1; dx <= 1; dx += 2) {
          const double ex = lum(x + dx, y), ey = lum(x, y + dy);
          m = std::max(
              {m, 0.5 * (c + ex), 0.5 * (c + ey), 0.25 * (c + ex + ey + lum(x + dx, y + dy))});
        }
      f[size_t(y) * w + x] = (m + 1e-4) * sin_max;  // keep every texel reachable
    }
  }
  return f;
}
}  // namespace

Lights::Lights(const Scene& scene, const Accel& accel) : scene_(scene) {
  const Bounds3 b = accel.bounds();
  if (!b.empty()) {
    scene_center_ = b.center();
    scene_radius_ = std::max(1e-3, 0.5 * length(b.diagonal()));
  }
  std::vector<double> power;  // each emitter's, by index: what picks them
  for (const Light& l : scene.lights) add_punctual(l, power);
  for (uint32_t id = 0; id < accel.object_count(); ++id) {
    const Accel::Record& rec = accel.record(id);
    if (rec.kind == Accel::Record::Kind::FlatMesh) {
      add_emissive_mesh(id, *rec.mesh, nullptr, 0, power);
    } else if (rec.kind == Accel::Record::Kind::Instance) {
      for (uint32_t j = 0; j < rec.proto->meshes.size(); ++j)
        add_emissive_mesh(id, rec.proto->meshes[j], &rec.world_from_object, j, power);
    } else if (rec.shape->kind == AnalyticShape::Kind::Sphere) {
      add_emissive_sphere(id, rec, power);
    }
  }
  if (scene.environment.present()) add_environment(power);
  build_pick(power);
  std::vector<double> area_power;
  for (uint32_t i = 0; i < emitters_.size(); ++i) {
    const auto k = emitters_[i].kind;
    if (k == Emitter::Kind::Point || k == Emitter::Kind::Spot || k == Emitter::Kind::Directional) {
      delta_.push_back(i);
    } else if (k != Emitter::Kind::Environment) {  // Whitted lights with the environment as ambient
      area_.push_back(i);
      area_power.push_back(power[i]);
    }
  }
  if (!area_.empty()) area_pick_ = Distribution1D(area_power);
}

void Lights::add_punctual(const Light& l, std::vector<double>& power) {
  Emitter e{};
  e.L = l.intensity;
  e.p0 = l.position;
  e.dir = normalize(l.direction);
  e.range = l.range;
  switch (l.kind) {
    case Light::Kind::Point:
      e.kind = Emitter::Kind::Point;
      power.push_back(4 * kPi * luminance(e.L));
      break;
    case Light::Kind::Spot:
      e.kind = Emitter::Kind::Spot;
      e.cos_inner = std::cos(radians(l.cone_angle));
      e.cos_outer = std::cos(radians(std::min(180.0, l.cone_angle + l.cone_falloff)));
      e.falloff = l.spot_falloff;
      if (l.cone_angle + l.cone_falloff > 0)
        e.cycles_band = (1 - e.cos_outer) * (1 - l.cone_angle / (l.cone_angle + l.cone_falloff));
      power.push_back(2 * kPi * (1 - 0.5 * (e.cos_inner + e.cos_outer)) * luminance(e.L));
      break;
    case Light::Kind::Directional:
      e.kind = Emitter::Kind::Directional;
      power.push_back(kPi * scene_radius_ * scene_radius_ * luminance(e.L));
      break;
  }
  emitters_.push_back(e);
}

// Every triangle of an emissive mesh (in world space through xf, when it is an instance's).
void Lights::add_emissive_mesh(uint32_t id, const TriangleMesh& m, const Transform* xf,
                               uint32_t mesh_index, std::vector<double>& power) {
  const Material& mat = *scene_.materials[m.material];
  if (!mat.is_emissive()) return;
  const Color scale = mat.emission.value * mat.emission_strength;
  for (size_t t = 0; t < m.triangle_count(); ++t) {
    Emitter e{};
    e.kind = Emitter::Kind::Triangle;
    const uint32_t* ix = &m.indices[t * 3];
    Vec3 p[3];
    Vec2 uv[3];
    for (int k = 0; k < 3; ++k) {
      p[k] = Vec3(m.positions[ix[k]]);
      if (xf) p[k] = xf->point(p[k]);
      uv[k] = m.uvs.empty() ? Vec2{} : Vec2{m.uvs[ix[k]].x, m.uvs[ix[k]].y};
    }
    e.p0 = p[0], e.p1 = p[1], e.p2 = p[2];
    e.uv0 = uv[0], e.uv1 = uv[1], e.uv2 = uv[2];
    e.area = triangle_area(p[0], p[1], p[2]);
    if (!(e.area > 0)) continue;
    e.material = &mat;
    e.two_sided = mat.double_sided;
    e.L = scale;
    by_surface_[{id, mesh_index, uint32_t(t)}] = uint32_t(emitters_.size());
    emitters_.push_back(e);
    power.push_back(e.area * kPi * (e.two_sided ? 2 : 1) * std::max(1e-6, luminance(scale)));
  }
}

void Lights::add_emissive_sphere(uint32_t id, const Accel::Record& rec,
                                 std::vector<double>& power) {
  const Material& mat = *scene_.materials[rec.shape->material];
  if (!mat.is_emissive()) return;
  Emitter e{};
  e.kind = Emitter::Kind::Sphere;
  e.p0 = rec.world_from_object.point({0, 0, 0});
  // Spheres are placed by translation (and the object transform); take its mean scale.
  e.radius =
      rec.shape->radius * std::cbrt(std::abs(dot(cross(rec.world_from_object.vector({1, 0, 0}),
                                                       rec.world_from_object.vector({0, 1, 0})),
                                                 rec.world_from_object.vector({0, 0, 1}))));
  e.material = &mat;
  e.L = mat.emission.value * mat.emission_strength;
  by_surface_[{id, 0, 0}] = uint32_t(emitters_.size());
  emitters_.push_back(e);
  power.push_back(4 * kPi * e.radius * e.radius * kPi * luminance(e.L));
}

// The environment, with an image's luminance (times sin theta, both bounded over each texel) as
// the distribution to sample.
void Lights::add_environment(std::vector<double>& power) {
  const Environment& env = scene_.environment;
  Emitter e{};
  e.kind = Emitter::Kind::Environment;
  e.L = env.color * env.strength;
  double avg = luminance(e.L);
  env_average_ = e.L;
  if (env.image) {
    const Image& im = *env.image;
    double sum = 0, weight = 0;
    Color csum;
    for (int y = 0; y < im.height; ++y) {
      const double sin_t = std::sin(kPi * (y + 0.5) / im.height);
      for (int x = 0; x < im.width; ++x) {
        const Color c{im.at(x, y, 0), im.at(x, y, 1), im.at(x, y, 2)};
        csum += c * sin_t;
        weight += sin_t;
        sum += luminance(c) * sin_t;
      }
    }
    env_dist_ =
        Distribution2D(environment_sampling_weights(im), size_t(im.width), size_t(im.height));
    env_average_ = csum / std::max(weight, 1e-30) * env.strength;
    avg = env.strength * sum / (double(im.width) * im.height) * 2;  // ~ mean over the sphere
  }
  env_index_ = int(emitters_.size());
  emitters_.push_back(e);
  env_luminance_ = std::max(1e-6, avg);
  power.push_back(kPi * scene_radius_ * scene_radius_ * kPi * env_luminance_);
}

Vec2 Lights::env_uv(const Vec3& d) const {
  const double phi = std::atan2(d.x, -d.z) - radians(scene_.environment.rotation);
  double u = phi / (2 * kPi) + 0.5;
  u -= std::floor(u);
  const double v = std::acos(std::clamp(d.y, -1.0, 1.0)) / kPi;
  return {u, v};
}

Vec3 Lights::env_dir(Vec2 uv) const {
  const double phi = 2 * kPi * (uv.x - 0.5) + radians(scene_.environment.rotation);
  const double theta = kPi * uv.y;
  const double s = std::sin(theta);
  return {s * std::sin(phi), std::cos(theta), -s * std::cos(phi)};
}

Color Lights::environment(const Vec3& d) const {
  const Environment& env = scene_.environment;
  if (!env.image) return env.color * env.strength;
  const Vec2 uv = env_uv(d);
  const Image& im = *env.image;
  // Bilinear, wrapping in u and clamping in v.
  const double x = uv.x * im.width - 0.5,
               y = std::clamp(uv.y * im.height - 0.5, 0.0, im.height - 1.0);
  const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
  const double tx = x - x0, ty = y - y0;
  auto px = [&](int xi, int yi) {
    xi = ((xi % im.width) + im.width) % im.width;
    yi = std::clamp(yi, 0, im.height - 1);
    return Color{im.at(xi, yi, 0), im.at(xi, yi, 1), im.at(xi, yi, 2)};
  };
  const Color c = (px(x0, y0) * (1 - tx) + px(x0 + 1, y0) * tx) * (1 - ty) +
                  (px(x0, y0 + 1) * (1 - tx) + px(x0 + 1, y0 + 1) * tx) * ty;
  return c * env.strength;
}

double Lights::pdf_environment(const Vec3& d, const Vec3& p, const Vec3& n) const {
  if (env_index_ < 0) return 0;
  const double pick = pick_pmf(size_t(env_index_), p, n);
  if (!scene_.environment.image) {
    return pick * cosine_hemisphere_pdf(std::max(0.0, dot(d, n)));
  }
  const Vec2 uv = env_uv(d);
  const double s = std::sin(kPi * uv.y);
  if (s <= 0) return 0;
  return pick * env_dist_.pdf(uv) / (2 * kPi * kPi * s);
}

double Lights::punctual_factor(const Emitter& e, const Vec3& wi, double dist) {
  double f = 1;
  if (e.range > 0) {
    const double r = dist / e.range, w = std::clamp(1 - r * r * r * r, 0.0, 1.0);
    f = w * w;
  }
  if (e.kind != Emitter::Kind::Spot) return f;
  const double c = dot(-wi, e.dir);
  if (c <= e.cos_outer) return 0;
  switch (e.falloff) {
    case Light::SpotFalloff::Smoothstep:
      if (c < e.cos_inner) {
        const double t = (c - e.cos_outer) / (e.cos_inner - e.cos_outer);
        f *= t * t * (3 - 2 * t);
      }
      return f;
    case Light::SpotFalloff::Gltf:
      if (c < e.cos_inner) {
        const double t = (c - e.cos_outer) / (e.cos_inner - e.cos_outer);
        f *= t * t;
      }
      return f;
    case Light::SpotFalloff::Cycles: {
      const double x = c - e.cos_outer;
      if (x < e.cycles_band) {
        const double t = x / e.cycles_band;
        f *= t * t * (3 - 2 * t);
      }
      return f * c;
    }
  }
  return f;
}

Color Lights::emission_at(const Emitter& e, Vec2 uv) const {
  if (!e.material || e.material->emission.kind == Texture::Kind::Constant) return e.L;
  TexCoord tc;
  tc.uv = uv;
  return e.material->emission.eval(tc) * e.material->emission_strength;
}

bool Lights::sample_from(size_t i, const Vec3& p, const Vec3* n, Vec2 u, LightSample* out) const {
  const Emitter& e = emitters_[i];
  switch (e.kind) {
    case Emitter::Kind::Point:
    case Emitter::Kind::Spot:
      return sample_punctual(e, p, out);
    case Emitter::Kind::Directional:
      out->wi = -e.dir;
      out->dist = kInf;
      out->L = e.L;
      out->pdf = 1;
      out->delta = true;
      return true;
    case Emitter::Kind::Triangle:
      return sample_triangle(e, p, u, out);
    case Emitter::Kind::Sphere:
      return sample_sphere(e, p, u, out);
    case Emitter::Kind::Environment:
      return sample_environment(n, u, out);
  }
  return false;
}

bool Lights::sample_punctual(const Emitter& e, const Vec3& p, LightSample* out) {
  const Vec3 d = e.p0 - p;
  const double d2 = dot(d, d);
  if (!(d2 > 0)) return false;
  out->dist = std::sqrt(d2);
  out->wi = d / out->dist;
  const double falloff = punctual_factor(e, out->wi, out->dist);
  if (!(falloff > 0)) return false;
  out->L = e.L * (falloff / d2);
  out->pdf = 1;
  out->delta = true;
  return true;
}

bool Lights::sample_triangle(const Emitter& e, const Vec3& p, Vec2 u, LightSample* out) const {
  const Vec2 b = sample_uniform_triangle(u);
  const Vec3 q = e.p0 * b.x + e.p1 * b.y + e.p2 * (1 - b.x - b.y);
  const Vec3 n = normalize(cross(e.p1 - e.p0, e.p2 - e.p0));
  const Vec3 d = q - p;
  const double d2 = dot(d, d);
  if (!(d2 > 0)) return false;
  out->dist = std::sqrt(d2);
  out->wi = d / out->dist;
  const double cos_l = dot(-out->wi, n);
  if (std::abs(cos_l) < 1e-12 || (!e.two_sided && cos_l < 0)) return false;
  out->pdf = d2 / (std::abs(cos_l) * e.area);
  out->L = emission_at(e, e.uv0 * b.x + e.uv1 * b.y + e.uv2 * (1 - b.x - b.y));
  out->delta = false;
  return true;
}

// Uniform in the cone of directions the sphere subtends.
bool Lights::sample_sphere(const Emitter& e, const Vec3& p, Vec2 u, LightSample* out) {
  const Vec3 dc = e.p0 - p;
  const double dc2 = dot(dc, dc);
  if (dc2 <= e.radius * e.radius) return false;  // inside the light
  const double cone = sphere_cone_one_minus_cos(e.radius * e.radius, dc2);
  if (!(cone > 0)) return false;  // it subtends no solid angle in double precision
  const Frame f = Frame::from_normal(dc / std::sqrt(dc2));
  const Vec3 w = f.to_world(sample_uniform_cone(u, cone));
  // Distance to the sphere along w.
  const double b = dot(dc, w);
  const double disc = b * b - (dc2 - e.radius * e.radius);
  out->dist = b - std::sqrt(std::max(0.0, disc));
  out->wi = w;
  out->pdf = uniform_cone_pdf(cone);
  out->L = e.L;
  out->delta = false;
  return true;
}

bool Lights::sample_environment(const Vec3* n, Vec2 u, LightSample* out) const {
  if (!scene_.environment.image && !n) {
    out->wi = sample_uniform_sphere(u);
    out->pdf = uniform_sphere_pdf();
  } else if (!scene_.environment.image) {
    const Vec3 w = Frame::from_normal(*n).to_world(sample_cosine_hemisphere(u));
    out->wi = normalize(w);
    out->pdf = cosine_hemisphere_pdf(dot(out->wi, *n));
    if (!(out->pdf > 0)) return false;
  } else {
    double pdf_uv;
    const Vec2 uv = env_dist_.sample(u, &pdf_uv);
    const double s = std::sin(kPi * uv.y);
    if (!(s > 0) || !(pdf_uv > 0)) return false;
    out->wi = env_dir(uv);
    out->pdf = pdf_uv / (2 * kPi * kPi * s);
  }
  out->dist = kInf;
  out->L = environment(out->wi);
  out->delta = false;
  return true;
}

Color Lights::emitted(const Hit& h, const Vec3& wo) const {
  const Material& m = *scene_.materials[h.material];
  if (!m.is_emissive()) return {};
  if (!m.double_sided && dot(wo, h.ng) <= 0) return {};
  TexCoord tc;
  tc.uv = h.uv;
  return m.emission.eval(tc) * m.emission_strength;
}

double Lights::pdf_emitter(const Hit& h, const Vec3& from, const Vec3& from_n,
                           const Vec3& wi) const {
  auto it = by_surface_.find({h.object_id, h.mesh, h.prim});
  if (it == by_surface_.end()) return 0;
  const Emitter& e = emitters_[it->second];
  const double pick = pick_pmf(it->second, from, from_n);
  if (!(pick > 0)) return 0;
  if (e.kind == Emitter::Kind::Triangle) {
    const double cos_l = std::abs(dot(wi, h.ng));
    if (cos_l < 1e-12) return 0;
    const double d2 = length_squared(h.p - from);
    return pick * d2 / (cos_l * e.area);
  }
  const double dc2 = length_squared(e.p0 - from);
  if (dc2 <= e.radius * e.radius) return 0;
  const double cone = sphere_cone_one_minus_cos(e.radius * e.radius, dc2);
  return cone > 0 ? pick * uniform_cone_pdf(cone) : 0.0;
}

}  // namespace anamorph
