#include "render/renderer.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>

#include "accel/accel.h"
#include "math/parallel.h"
#include "render/adaptive.h"
#include "render/integrator.h"
#include "render/lights.h"
#include "render/sampler.h"
#include "render/shading.h"

namespace anamorph {

namespace {

enum class Mode { Radiance, Albedo, Normal, Depth, Position, Id, Uv };

Mode mode_of(IntegratorKind integrator) {
  switch (integrator) {
    case IntegratorKind::Albedo:
      return Mode::Albedo;
    case IntegratorKind::Normal:
      return Mode::Normal;
    case IntegratorKind::Depth:
      return Mode::Depth;
    case IntegratorKind::Position:
      return Mode::Position;
    case IntegratorKind::Id:
      return Mode::Id;
    case IntegratorKind::Uv:
      return Mode::Uv;
    case IntegratorKind::Whitted:
    case IntegratorKind::Path:
      break;
  }
  return Mode::Radiance;
}

// A stable, well-spread colour for an object id.
Color id_color(double id) {
  const uint64_t h = mix64(uint64_t(id + 1));
  return {double(h & 0xff) / 255, double((h >> 8) & 0xff) / 255, double((h >> 16) & 0xff) / 255};
}

Color aov_beauty(Mode m, const AovSample& a) {
  if (!a.hit) return {};
  switch (m) {
    case Mode::Albedo:
      return a.albedo;
    case Mode::Normal:
      return a.normal * 0.5 + Vec3(0.5);
    case Mode::Depth:
      return Color(a.depth);
    case Mode::Position:
      return a.position;
    case Mode::Id:
      return id_color(a.id);
    case Mode::Uv:
      return {a.uv.x, a.uv.y, 0};
    default:
      return {};
  }
}

struct Tile {
  int x0, y0, x1, y1;
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

// Everything one render call shares between its tiles.
struct Renderer::Job {
  const Renderer& r;
  const RenderSettings& rs;
  Mode mode;
  std::unique_ptr<Integrator> integrator;
  SamplerKind sampler;
  bool gaussian;
  bool want_aovs;  // AOV values: for the film's layers or an AOV integrator
  bool film_aovs;  // the film has AOV layers
  // Whether primary hits need their surface geometry (points, normals, uv): not for depth, ids
  // or albedo without textures when there are no AOV layers.
  bool hit_surface;
  int W, H;
  double du, dv;  // one pixel, in image units (ray differentials)
  // Uniform sampling: each sample's share of a pixel, as a footprint scale (1/sqrt(spp)).
  double uniform_scale;
  std::vector<uint8_t> textured;  // per material: some texture is not a constant

  Job(const Renderer& rr, const RenderContext& ctx, const Film& film, bool aovs)
      : r(rr),
        rs(rr.scene_.render),
        mode(mode_of(rs.integrator)),
        integrator(mode == Mode::Radiance ? make_integrator(rs.integrator, ctx) : nullptr),
        sampler(rs.sampler),
        gaussian(rs.filter == PixelFilter::Gaussian),
        want_aovs(aovs || mode != Mode::Radiance),
        film_aovs(aovs),
        W(film.width()),
        H(film.height()) {
    // A sample filters textures over its share of the pixel: 1/sqrt(spp) of it with uniform
    // sampling; adaptive subdivision passes the lattice spacing each sample stands for, and
    // per-pixel adaptive sampling the share given by the samples the pixel has once the pass ends.
    uniform_scale = footprint_scale(rs.spp);
    du = 1.0 / W;
    dv = 1.0 / H;
    for (const Material& m : rr.scene_.materials)
      textured.push_back(m.base_color.kind != Texture::Kind::Constant || m.has_normal_map ||
                         m.metallic_roughness.kind != Texture::Kind::Constant ||
                         m.emission.kind != Texture::Kind::Constant);
    const bool any_texture = std::find(textured.begin(), textured.end(), 1) != textured.end();
    hit_surface = film_aovs || !(mode == Mode::Depth || mode == Mode::Id ||
                                 (mode == Mode::Albedo && !any_texture));
  }

  // The share of a pixel one of n samples stands for, as a footprint scale (never below 1/8
  // pixel: finer footprints only add texture noise).
  static double footprint_scale(uint32_t n) {
    return std::max(0.125, 1.0 / std::sqrt(double(std::max(1u, n))));
  }

  // Completes a camera sample whose first hit is known. `footprint` is the sample's share of a
  // pixel as a scale of the pixel's footprint; `cam_ray()` gives the camera ray with its
  // differentials (asked for only where a footprint is needed: primary packets hold their rays as
  // arrays). Writes into `out` (reused by the caller: building a fresh result per sample meant
  // zeroing ~150 bytes per ray, a visible cost for primary-ray renders).
  template <class CamRay>
  void finish(const Ray& ray, const CamRay& cam_ray, const Hit* hit, Rng& rng, uint64_t& rays,
              SampleResult& out, double footprint = 1) const {
    out.alpha = 1;
    out.aov.hit = false;
    Footprint fp;
    // Footprints only matter where something is filtered: textures, or rays that go on (their
    // ray cones carry it to textures further along).
    if (hit && (mode == Mode::Radiance || textured[hit->material]))
      fp = footprint_at(cam_ray(), du * footprint, dv * footprint, *hit);
    if (want_aovs && hit) {
      // Every field for AOV layers; otherwise only the one the AOV integrator shows.
      const bool all = film_aovs;
      const Material& m = r.scene_.materials[hit->material];
      out.aov.hit = true;
      if (all || mode == Mode::Albedo)
        out.aov.albedo =
            textured[hit->material] ? m.base_color.eval(texcoord_at(*hit, fp)) : m.base_color.value;
      if (all || mode == Mode::Normal)
        out.aov.normal = dot(hit->ns, ray.d) > 0 ? -hit->ns : hit->ns;
      if (all || mode == Mode::Position) out.aov.position = hit->p;
      // Distance along the camera ray from its origin (dir is unit).
      if (all || mode == Mode::Depth) out.aov.depth = hit->t;
      if (all || mode == Mode::Id) out.aov.id = hit->object_id;
      if (all || mode == Mode::Uv) out.aov.uv = hit->uv;
    }
    out.L = mode == Mode::Radiance ? integrator->radiance(ray, hit, fp, rng, rays)
                                   : aov_beauty(mode, out.aov);
  }

  // One full camera sample at image position uv (single ray; adaptive subdivision, tests).
  // The camera sample at image position uv: lens and time drawn from rng when the camera uses them.
  CameraSample camera_sample(Vec2 uv, Rng& rng) const {
    CameraSample cs;
    cs.uv = uv;
    if (r.scene_.camera->uses_lens_or_time()) {
      cs.lens = {rng.uniform(), rng.uniform()};
      cs.time = rng.uniform();
    }
    return cs;
  }

  SampleResult sample_at(Vec2 uv, Rng& rng, uint64_t& rays, double footprint = 1) const {
    const auto cam = r.scene_.camera->generate(camera_sample(uv, rng));
    if (!cam) return SampleResult{};  // no ray: transparent
    const Ray ray{cam->org, cam->dir, 0, kInf};
    Hit h;
    ++rays;
    const bool found = r.accel_->intersect(ray, &h);
    SampleResult out;
    finish(
        ray, [&] { return *cam; }, found ? &h : nullptr, rng, rays, out, footprint);
    return out;
  }

  // kCameraBatch lattice points of adaptive sampling as sample_at gives them (each lane's random
  // numbers from its key, its footprint as given), the camera rays generated as a batch and
  // traced as one packet.
  void lattice_samples(const Vec2* uv, const uint64_t* keys, const double* footprints,
                       const bool* use, SampleResult* out, uint64_t& rays,
                       CameraRayBatch* keep) const {
    constexpr int N = kCameraBatch;
    CameraSample cs[N];
    Rng rng[N];
    for (int k = 0; k < N; ++k) {
      rng[k] = Rng(keys[k], rs.seed);
      cs[k] = camera_sample(uv[k], rng[k]);
    }
    CameraRayBatch local;
    CameraRayBatch& cam = keep ? *keep : local;
    r.scene_.camera->generate_batch(cs, N, &cam);
    bool valid[N], found[N];
    Hit hits[N];
    for (int k = 0; k < N; ++k) valid[k] = use[k] && cam.valid[k];
    r.accel_->intersect16(cam.org, cam.dir, valid, hits, found);
    for (int k = 0; k < N; ++k) {
      if (!valid[k]) {
        out[k] = SampleResult{};  // no ray (or not wanted): transparent
        continue;
      }
      ++rays;
      finish(
          Ray{cam.origin(k), cam.direction(k), 0, kInf}, [&] { return cam.ray(k); },
          found[k] ? &hits[k] : nullptr, rng[k], rays, out[k], footprints[k]);
    }
  }
};

Renderer::Renderer(const Scene& scene)
    : scene_(scene),
      accel_(std::make_unique<Accel>(scene)),
      lights_(std::make_unique<Lights>(scene, *accel_)) {}

Renderer::~Renderer() = default;

namespace {

struct TileStats {
  uint64_t rays = 0, samples = 0, nans = 0;
  int nan_x = -1, nan_y = -1, nan_s = -1;
  void nan(int x, int y, int s) {
    if (nans++ == 0) nan_x = x, nan_y = y, nan_s = s;
  }
};

void merge(RenderStats& stats, const std::vector<TileStats>& tiles) {
  for (const TileStats& st : tiles) {
    stats.rays += st.rays;
    stats.samples += st.samples;
    if (!st.nans) continue;
    // Keep the first in (y, x, sample) order so reports do not depend on scheduling.
    const bool earlier =
        stats.nan_samples == 0 || st.nan_y < stats.nan_y ||
        (st.nan_y == stats.nan_y &&
         (st.nan_x < stats.nan_x || (st.nan_x == stats.nan_x && st.nan_s < stats.nan_sample)));
    if (earlier) stats.nan_x = st.nan_x, stats.nan_y = st.nan_y, stats.nan_sample = st.nan_s;
    stats.nan_samples += st.nans;
  }
}

}  // namespace

RenderStats Renderer::render(Film& film, const RenderOptions& opt) const {
  const auto t0 = std::chrono::steady_clock::now();
  const RenderSettings& rs = scene_.render;
  const RenderContext ctx{scene_, *accel_, *lights_, rs.max_depth, rs.bailout, opt.cancel};
  const Job job(*this, ctx, film, !opt.aovs.empty());
  const int W = film.width(), H = film.height();
  const bool corners = rs.adaptive() && rs.antialias == Antialias::Lattice;
  const bool per_pixel = rs.adaptive() && rs.antialias == Antialias::Pixel;
  // Whitted's samples of a pixel differ only by where they fall in it (a deterministic
  // integrand, whose scrambled-Sobol' estimate converges faster than noise): its own rule.
  const StopRule stop_rule = rs.integrator == IntegratorKind::Whitted
                                 ? StopRule::deterministic(rs.noise_threshold)
                                 : StopRule::noisy(rs.noise_threshold);

  std::vector<Tile> tiles;
  const int ts = rs.tile_size;
  for (int y = 0; y < H; y += ts)
    for (int x = 0; x < W; x += ts)
      tiles.push_back({x, y, std::min(x + ts, W), std::min(y + ts, H)});

  RenderStats stats;
  std::mutex mu;
  uint64_t work_done = 0, rays_done = 0;
  tbb::task_arena arena(opt.threads > 0 ? opt.threads : tbb::task_arena::automatic);
  auto report = [&](uint64_t work, uint64_t work_total, uint64_t rays, int pass, int passes) {
    if (!opt.on_progress) return;
    std::lock_guard<std::mutex> lock(mu);
    work_done += work;
    rays_done += rays;
    Progress p;
    p.fraction = std::min(1.0, double(work_done) / double(std::max<uint64_t>(1, work_total)));
    p.seconds = seconds_since(t0);
    p.rays = rays_done;
    p.pass = pass;
    p.passes = passes;
    opt.on_progress(p);
  };
  const auto cancelled = [&] { return ctx.cancelled(); };

  if (corners) {
    // The paper's adaptive supersampling: corners shared between pixels, squares split where
    // they differ, stretched pixels split from the start.
    const AdaptiveGrid grid(*scene_.camera, W, H, rs, accel_->bounds());
    tbb::enumerable_thread_specific<AdaptiveWorkspace> spaces;
    std::vector<TileStats> tile_stats(tiles.size());
    arena.execute([&] {
      parallel_chunks(0, tiles.size(), 1, [&](size_t first_tile, size_t end_tile) {
        for (size_t ti = first_tile; ti != end_tile; ++ti) {
          if (cancelled()) return;
          const Tile& t = tiles[ti];
          TileStats& st = tile_stats[ti];
          AdaptiveWorkspace& ws = spaces.local();
          const AdaptiveGrid::EvalBatch eval =
              [&](const Vec2* uv, const uint64_t* keys, const double* footprints, const bool* use,
                  SampleResult* out, uint64_t& rays, CameraRayBatch* cam) {
                job.lattice_samples(uv, keys, footprints, use, out, rays, cam);
              };
          grid.render_tile(
              t.x0, t.y0, t.x1, t.y1, ws, eval,
              [&](int x, int y, const PixelResult& p) {
                AovSample a;
                if (job.want_aovs && !film.aovs().empty()) {
                  Rng rng(mix64(uint64_t(y) * 0x9E3779B97F4A7C15ULL + uint64_t(x)), rs.seed);
                  a = job.sample_at({(x + 0.5) / W, (y + 0.5) / H}, rng, st.rays).aov;
                }
                if (p.nans) st.nan(x, y, 0);
                film.set(x, y, p.L, p.alpha, p.samples, a);
              },
              st.rays, st.samples);
          report(uint64_t(t.x1 - t.x0) * (t.y1 - t.y0), uint64_t(W) * H, st.rays, 0, 1);
        }
      });
    });
    merge(stats, tile_stats);
    stats.cancelled = cancelled();
    stats.seconds = seconds_since(t0);
    if (!stats.cancelled && opt.on_pass) opt.on_pass(film, 0);
    return stats;
  }

  // Sample passes: progressive 1, 1, 2, 4, ... samples per pixel; with per-pixel adaptive sampling
  // the same schedule from min_spp on, skipping pixels whose neighbourhood has converged.
  const auto spp = uint32_t(per_pixel ? rs.max_spp : rs.spp);
  std::vector<uint32_t> pass_end;
  if (opt.progressive || per_pixel) {
    uint32_t done = 0, step = per_pixel ? uint32_t(rs.min_spp) : 1;
    while (done < spp) {
      done = std::min(spp, done + step);
      pass_end.push_back(done);
      if (pass_end.size() > 1) step *= 2;
    }
  } else {
    pass_end.push_back(spp);
  }
  // Which pixels still take samples (per-pixel adaptive sampling only; empty means all of them).
  std::vector<uint8_t> active(per_pixel ? size_t(W) * H : 0, 1);
  const bool lens_time = scene_.camera->uses_lens_or_time();
  const bool needs_rng =
      lens_time || job.mode == Mode::Radiance || job.sampler != SamplerKind::Center;
  // Stratified sampling: pixel position, lens, time and the first three bounces' light and BSDF
  // numbers come from the pixel's scrambled Sobol' points (any prefix of a pixel's samples is
  // well stratified, which per-pixel adaptive sampling needs: a pixel may stop after any pass).
  const bool qmc = needs_rng && job.sampler == SamplerKind::Stratified;
  // Without random numbers (pixel centers) every sample sits at this offset in its pixel.
  const Vec2 fixed_offset = job.gaussian
                                ? gaussian_offset({0.5, 0.5}, rs.filter_radius) + Vec2{0.5, 0.5}
                                : Vec2{0.5, 0.5};
  constexpr int kQmcDims = 24;
  const uint64_t work_total = uint64_t(W) * H * spp;

  uint32_t s_begin = 0;
  for (size_t pass = 0; pass < pass_end.size(); ++pass) {
    const uint32_t s_end = pass_end[pass];
    // Texture footprints: with per-pixel adaptive sampling a pixel that takes this pass's samples
    // ends with at least s_end of them, and each sample stands for that share of the pixel (a
    // function of the sample index alone, so tiles and threads agree). Earlier, wider samples blur
    // a little; the old fixed 1/sqrt(render.spp) (spp = 1 unless given) blurred every sample over
    // the whole pixel.
    const double fp_scale = per_pixel ? Job::footprint_scale(s_end) : job.uniform_scale;
    std::vector<TileStats> tile_stats(tiles.size());
    arena.execute([&] {
      parallel_chunks(0, tiles.size(), 1, [&](size_t first_tile, size_t end_tile) {
        for (size_t ti = first_tile; ti != end_tile; ++ti) {
          if (cancelled()) return;
          const Tile& t = tiles[ti];
          TileStats& st = tile_stats[ti];
          // Coherent packets of 4x4 pixels for the primary rays. The packet's arrays live for
          // the whole tile: constructing them per packet (zeroing about 6 KB) cost a third of
          // the time of primary-ray renders.
          constexpr int kPacket = kCameraBatch;
          CameraRayBatch cam;
          bool valid[kPacket], found[kPacket], use[kPacket];
          Hit hits[kPacket];
          Rng rng[kPacket];
          CameraSample samples[kPacket];
          int lx[kPacket], ly[kPacket];
          SampleResult res;
          // Cancellation is checked for every packet, so a tile of a million samples per pixel
          // (or of deep ray trees) stops within one packet's time.
          for (uint32_t s = s_begin; s < s_end && !cancelled(); ++s) {
            for (int y = t.y0; y < t.y1 && !cancelled(); y += 4)
              for (int x = t.x0; x < t.x1 && !cancelled(); x += 4) {
                if (!needs_rng) {
                  // Every sample at the same spot of its pixel: u per column, v per row.
                  double uc[4], vr[4];
                  bool col[4], row[4];
                  for (int i = 0; i < 4; ++i) {
                    uc[i] = std::clamp((x + i + fixed_offset.x) / W, 0.0, 1.0);
                    vr[i] = std::clamp((y + i + fixed_offset.y) / H, 0.0, 1.0);
                    col[i] = x + i < t.x1;
                    row[i] = y + i < t.y1;
                  }
                  for (int k = 0; k < kPacket; ++k) {
                    lx[k] = x + (k & 3);
                    ly[k] = y + (k >> 2);
                    use[k] = col[k & 3] && row[k >> 2] &&
                             (active.empty() || active[size_t(ly[k]) * W + lx[k]]);
                    samples[k] = CameraSample{};
                    if (use[k]) samples[k].uv = {uc[k & 3], vr[k >> 2]};
                  }
                } else {
                  for (int k = 0; k < kPacket; ++k) {
                    lx[k] = x + (k & 3);
                    ly[k] = y + (k >> 2);
                    use[k] = lx[k] < t.x1 && ly[k] < t.y1 &&
                             (active.empty() || active[size_t(ly[k]) * W + lx[k]]);
                    if (!use[k]) continue;
                    // AOV images of pinhole cameras at pixel centers use no random numbers at
                    // all.
                    if (needs_rng) {
                      rng[k] = Rng::for_sample(uint32_t(lx[k]), uint32_t(ly[k]), s, rs.seed);
                      if (qmc)
                        rng[k].qmc(s, mix64((uint64_t(ly[k]) << 32 | uint32_t(lx[k])) ^ rs.seed),
                                   kQmcDims);
                    }
                    Vec2 off;
                    if (qmc)
                      rng[k].uniform2(off.x, off.y);
                    else
                      off = pixel_offset(job.sampler, rng[k]);
                    if (job.gaussian) off = gaussian_offset(off, rs.filter_radius) + Vec2{0.5, 0.5};
                    CameraSample& cs = samples[k];
                    cs.uv = {std::clamp((lx[k] + off.x) / W, 0.0, 1.0),
                             std::clamp((ly[k] + off.y) / H, 0.0, 1.0)};
                    if (lens_time) {
                      rng[k].uniform2(cs.lens.x, cs.lens.y);
                      cs.time = rng[k].uniform();
                    }
                  }
                  // Unused lanes get a harmless sample; their rays are masked out below.
                  for (int k = 0; k < kPacket; ++k)
                    if (!use[k]) samples[k] = CameraSample{};
                }
                scene_.camera->generate_batch(samples, kPacket, &cam);
                for (int k = 0; k < kPacket; ++k) valid[k] = cam.valid[k] && use[k];
                accel_->intersect16(cam.org, cam.dir, valid, hits, found, job.hit_surface);
                for (int k = 0; k < kPacket; ++k) {
                  if (!use[k]) continue;
                  st.samples++;
                  if (!valid[k]) {
                    film.add(lx[k], ly[k], {}, 0, AovSample{}, s == 0);  // no ray: transparent
                    continue;
                  }
                  st.rays++;
                  job.finish(
                      Ray{cam.origin(k), cam.direction(k), 0, kInf}, [&] { return cam.ray(k); },
                      found[k] ? &hits[k] : nullptr, rng[k], st.rays, res, fp_scale);
                  if (!is_finite(res.L)) {
                    st.nan(lx[k], ly[k], int(s));
                    if (s == 0) film.reset(lx[k], ly[k]);  // no sample yet
                    continue;                              // dropped
                  }
                  film.add(lx[k], ly[k], res.L, res.alpha, res.aov, s == 0);
                }
              }
          }
          report(uint64_t(t.x1 - t.x0) * (t.y1 - t.y0) * (s_end - s_begin), work_total, st.rays,
                 int(pass), int(pass_end.size()));
        }
      });
    });
    merge(stats, tile_stats);
    if (cancelled()) {
      stats.cancelled = true;
      break;
    }
    if (opt.on_pass) opt.on_pass(film, int(pass));
    s_begin = s_end;
    if (per_pixel) {
      if (rs.time_limit > 0 && seconds_since(t0) > rs.time_limit) break;
      size_t still_active = 0;
      arena.execute([&] { still_active = update_active(film, stop_rule, &active); });
      if (still_active == 0) break;
    }
  }
  stats.seconds = seconds_since(t0);
  return stats;
}

}  // namespace anamorph
