#include "render/form_factors.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "camera/presets.h"
#include "math/frame.h"
#include "math/parallel.h"
#include "math/rng.h"
#include "render/integrator.h"
#include "render/lights.h"
#include "render/radiosity.h"
#include "render/surface_sampler.h"
#include "scene/scene_schema.h"

namespace anamorph {

namespace {

std::string record_name(const Accel::Record& r, uint32_t id) {
  std::string n;
  switch (r.kind) {
    case Accel::Record::Kind::FlatMesh:
      n = r.mesh->name;
      break;
    case Accel::Record::Kind::Instance:
      n = r.proto->name;
      break;
    case Accel::Record::Kind::Shape:
      n = r.shape->name.empty() ? std::string(name_of(r.shape->kind)) : r.shape->name;
      break;
  }
  return n.empty() ? "object" + std::to_string(id) : n;
}

// Unique names, in object order: an object keeps its name unless an earlier one has it; a
// repeated name gets the lowest "#2", "#3", ... that no object has. The environment column's name
// counts as taken (an object named so is listed as "environment#2", and a note says so).
}  // namespace

std::vector<std::string> form_factor_names(const Accel& accel, std::vector<std::string>* notes) {
  const size_t n = accel.object_count();
  std::vector<std::string> wanted(n), names(n);
  std::set<std::string> taken{std::string(kEnvironmentColumn)};
  for (uint32_t id = 0; id < n; ++id) {
    wanted[id] = record_name(accel.record(id), id);
    if (taken.insert(wanted[id]).second) names[id] = wanted[id];
  }
  for (size_t id = 0; id < n; ++id) {
    for (int k = 2; names[id].empty(); ++k)
      if (const std::string c = wanted[id] + "#" + std::to_string(k); taken.insert(c).second)
        names[id] = c;
    if (wanted[id] == kEnvironmentColumn)
      notes->push_back(fmt::format(
          "the object named '{}' is listed as '{}': '{}' names the column of rays that hit "
          "nothing",
          wanted[id], names[id], kEnvironmentColumn));
  }
  return names;
}

namespace {

int index_of(const std::vector<std::string>& names, const std::string& n) {
  const auto it = std::find(names.begin(), names.end(), n);
  if (it == names.end()) {
    std::string all;
    for (const auto& x : names) all += (all.empty() ? "" : ", ") + x;
    throw std::invalid_argument("no object named '" + n + "' (the scene has: " + all + ")");
  }
  return int(it - names.begin());
}

std::vector<bool> inward_flags(const std::vector<std::string>& names,
                               const std::vector<std::string>& inward) {
  std::vector<bool> flags(names.size(), false);
  for (const auto& name : inward) flags[size_t(index_of(names, name))] = true;
  return flags;
}

// The hemispherical camera: the orthographic fisheye over 180 degrees, r = sin(theta), whose
// image disk has equal projected solid angle per unit area (Nusselt's analog). Its rays, in its
// own space (looking along -z), at the centers of a jittered g x g grid.
struct Hemisphere {
  VirtualCamera camera{make_preset("fisheye", "fov = 180\nmapping = \"orthographic\"", {64, 64})};
  int g;
  explicit Hemisphere(int rays) : g(std::max(1, int(std::lround(std::sqrt(double(rays)))))) {}
  // Direction m of the grid in the frame around n (local z = n), turned by `spin`.
  std::optional<Vec3> direction(int m, Rng& rng, const Frame& f) const {
    const double u = (m % g + rng.uniform()) / g, v = (m / g + rng.uniform()) / g;
    const auto r = camera.generate(CameraSample{{u, v}});
    if (!r) return std::nullopt;  // outside the image circle
    return f.to_world({r->dir.x, r->dir.y, -r->dir.z});
  }
};

// A frame around n turned by a random angle (so that the grid's directions differ per point).
Frame spun_frame(const Vec3& n, double spin) {
  Frame f = Frame::from_normal(n);
  const double c = std::cos(spin), s = std::sin(spin);
  const Vec3 a = f.s * c + f.t * s, b = f.t * c - f.s * s;
  f.s = a, f.t = b;
  return f;
}

// Weighted sums over a source's points, per column: sum w, sum w F, sum w^2 F^2 ... enough for
// the weighted mean and its standard error.
struct Sums {
  double w = 0, w2 = 0;
  std::vector<double> wf, w2f, w2f2;
  explicit Sums(size_t cols) : wf(cols), w2f(cols), w2f2(cols) {}
  void add(double weight, const std::vector<double>& f) {
    w += weight, w2 += weight * weight;
    for (size_t c = 0; c < f.size(); ++c) {
      wf[c] += weight * f[c];
      w2f[c] += weight * weight * f[c];
      w2f2[c] += weight * weight * f[c] * f[c];
    }
  }
  void merge(const Sums& o) {
    w += o.w, w2 += o.w2;
    for (size_t c = 0; c < wf.size(); ++c)
      wf[c] += o.wf[c], w2f[c] += o.w2f[c], w2f2[c] += o.w2f2[c];
  }
  // The ratio estimate sum(w f) / sum(w) and its standard error, sqrt(sum w^2 (f - mean)^2) /
  // sum(w) (n / (n - 1) corrected).
  std::pair<double, double> mean_error(size_t c, int n) const {
    const double m = wf[c] / w;
    const double var = std::max(0.0, w2f2[c] - 2 * m * w2f[c] + m * m * w2);
    return {m, std::sqrt(var * n / std::max(1, n - 1)) / w};
  }
};

// Runs f(point, weight, rng, counts) over a source's origins in fixed chunks, merging per-chunk
// sums in chunk order: the same bits for any thread count. Weights are divided by the surface's
// reference weight (the ratio estimates do not change, and squared weights of a tiny or huge
// object stay within double precision); sums.w * reference / origins is the area.
template <class PerPoint>
Sums over_points(const MeasurableSurface& surface, int origins, size_t cols, uint64_t seed,
                 uint64_t stream, const std::atomic<bool>* cancel, PerPoint per_point) {
  const SurfaceSampler& sampler = *surface.sampler;
  constexpr int kChunk = 16;
  const int chunks = (origins + kChunk - 1) / kChunk;
  std::vector<Sums> partial(static_cast<size_t>(chunks), Sums(cols));
  parallel_for_each(0, chunks, [&](int c) {
    if (cancel && cancel->load(std::memory_order_relaxed)) return;
    std::vector<double> f(cols);
    for (int k = c * kChunk; k < std::min(origins, (c + 1) * kChunk); ++k) {
      if (cancel && cancel->load(std::memory_order_relaxed)) return;
      Rng rng((stream << 32) + uint64_t(k), seed);
      const SurfacePoint s = sampler.sample((k + rng.uniform()) / origins, rng.uniform());
      std::fill(f.begin(), f.end(), 0.0);
      per_point(s, rng, f);
      partial[size_t(c)].add(s.weight / surface.reference, f);
    }
  });
  Sums total(cols);
  for (const Sums& p : partial) total.merge(p);
  return total;
}

// Reciprocity (A_i F_ij = A_j F_ji) over the measured pairs: the worst pair's difference in
// standard errors.
void check_reciprocity(FormFactors& out) {
  for (size_t a = 0; a < out.rows.size(); ++a)
    for (size_t b = a + 1; b < out.rows.size(); ++b) {
      const size_t i = size_t(out.rows[a]), j = size_t(out.rows[b]);
      const double lhs = out.areas[i] * out.F[a][j], rhs = out.areas[j] * out.F[b][i];
      const double se = std::hypot(out.areas[i] * out.error[a][j], out.areas[j] * out.error[b][i]);
      const double z = se > 0 ? std::abs(lhs - rhs) / se : (lhs == rhs ? 0 : kInf);
      if (z > out.worst_reciprocity_z)
        out.worst_reciprocity_z = z, out.worst_i = int(i), out.worst_j = int(j);
    }
}

}  // namespace

FormFactors measure_form_factors(const Accel& accel, const FormFactorOptions& o) {
  FormFactors out;
  out.names = form_factor_names(accel, &out.notes);
  const size_t n = out.names.size(), cols = n + 1;
  const std::vector<bool> inward = inward_flags(out.names, o.inward);
  std::vector<int> wanted;
  for (const auto& name : o.sources) wanted.push_back(index_of(out.names, name));
  out.areas.assign(n, 0);
  out.no_row.assign(n, "");
  std::vector<MeasurableSurface> surfaces(n);
  for (size_t i = 0; i < n; ++i) {
    surfaces[i] = measurable_surface(accel.record(uint32_t(i)), inward[i]);
    if (surfaces[i].sampler) continue;
    if (std::find(wanted.begin(), wanted.end(), int(i)) != wanted.end())
      throw std::invalid_argument("'" + out.names[i] +
                                  "' has no row of form factors: " + surfaces[i].problem);
    if (o.sources.empty()) out.no_row[i] = surfaces[i].problem;
  }
  if (wanted.empty())
    for (size_t i = 0; i < n; ++i)
      if (surfaces[i].sampler) wanted.push_back(int(i));
  const Hemisphere hemi(o.rays);
  for (const int i : wanted) {
    if (o.cancel && o.cancel->load()) break;  // (the caller sees the flag)
    const Sums sums =
        over_points(surfaces[size_t(i)], o.origins, cols, o.seed, uint64_t(i), o.cancel,
                    [&](const SurfacePoint& s, Rng& rng, std::vector<double>& f) {
                      const Frame frame = spun_frame(s.n, 2 * kPi * rng.uniform());
                      int valid = 0;
                      for (int m = 0; m < hemi.g * hemi.g; ++m) {
                        const auto d = hemi.direction(m, rng, frame);
                        if (!d) continue;
                        ++valid;
                        Hit hit;
                        const Ray ray{s.p + s.n * ray_offset(s.p), *d};
                        f[accel.intersect(ray, &hit) ? hit.object_id : n] += 1;
                      }
                      for (double& x : f) x /= std::max(valid, 1);
                    });
    out.rows.push_back(i);
    out.areas[size_t(i)] = surfaces[size_t(i)].reference * (sums.w / o.origins);
    std::vector<double> row(cols), err(cols);
    // An entry no ray hit has a spread of zero, but all it shows is F < a few / rays: its error
    // is at least one ray's worth (so reciprocity against a tiny object is judged fairly).
    const double one_ray = 1.0 / (double(o.origins) * hemi.g * hemi.g * kPi / 4);
    for (size_t c = 0; c < cols; ++c) {
      std::tie(row[c], err[c]) = sums.mean_error(c, o.origins);
      err[c] = std::max(err[c], one_ray);
    }
    out.F.push_back(std::move(row));
    out.error.push_back(std::move(err));
  }
  check_reciprocity(out);
  return out;
}

PathRadiance path_traced_radiance(const Scene& scene, const Accel& accel, const FormFactors& f,
                                  const FormFactorOptions& o, int max_depth) {
  const Lights lights(scene, accel);
  const RenderContext ctx{scene, accel, lights, max_depth, 0, o.cancel};
  const auto path = make_integrator("path", ctx);
  const Hemisphere hemi(o.rays);
  const std::vector<bool> inward = inward_flags(f.names, o.inward);
  PathRadiance out;
  for (const int i : f.rows) {
    if (o.cancel && o.cancel->load()) break;  // (the caller sees the flag)
    const MeasurableSurface surface =
        measurable_surface(accel.record(uint32_t(i)), inward[size_t(i)]);
    const Color rho = object_reflectance(scene, accel, uint32_t(i));
    const Color le = object_emission(scene, accel, uint32_t(i)) / kPi;
    const Sums sums =
        over_points(surface, o.origins, 3, o.seed + 1, uint64_t(i), o.cancel,
                    [&](const SurfacePoint& s, Rng& rng, std::vector<double>& f3) {
                      const Frame frame = spun_frame(s.n, 2 * kPi * rng.uniform());
                      Color in;
                      int valid = 0;
                      uint64_t rays = 0;
                      for (int m = 0; m < hemi.g * hemi.g; ++m) {
                        const auto d = hemi.direction(m, rng, frame);
                        if (!d) continue;
                        ++valid;
                        const Ray ray{s.p + s.n * ray_offset(s.p), *d};
                        Hit hit;
                        const bool found = accel.intersect(ray, &hit);
                        in += path->radiance(ray, found ? &hit : nullptr, Footprint{}, rng, rays);
                      }
                      const Color out_radiance = le + rho * in / double(std::max(valid, 1));
                      for (int c = 0; c < 3; ++c) f3[size_t(c)] = out_radiance[c];
                    });
    Color m, e;
    for (int c = 0; c < 3; ++c) std::tie(m[c], e[c]) = sums.mean_error(size_t(c), o.origins);
    out.mean.push_back(m);
    out.error.push_back(e);
  }
  return out;
}

}  // namespace anamorph
