#include "render/renderer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>

#include "accel/accel.h"
#include "render/integrator.h"
#include "render/lights.h"
#include "render/sampler.h"
#include "render/shading.h"

namespace anamorph {

namespace {

enum class Mode { Radiance, Albedo, Normal, Depth, Position, Id, Uv };

Mode mode_of(const std::string& integrator) {
  if (integrator == "albedo") return Mode::Albedo;
  if (integrator == "normal") return Mode::Normal;
  if (integrator == "depth") return Mode::Depth;
  if (integrator == "position") return Mode::Position;
  if (integrator == "id") return Mode::Id;
  if (integrator == "uv") return Mode::Uv;
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
    case Mode::Albedo: return a.albedo;
    case Mode::Normal: return a.normal * 0.5 + Vec3(0.5);
    case Mode::Depth: return Color(a.depth);
    case Mode::Position: return a.position;
    case Mode::Id: return id_color(a.id);
    case Mode::Uv: return {a.uv.x, a.uv.y, 0};
    default: return {};
  }
}

struct Tile {
  int x0, y0, x1, y1;
};

struct TileStats {
  uint64_t rays = 0, samples = 0, nans = 0;
  int nan_x = -1, nan_y = -1, nan_s = -1;
};

}  // namespace

Renderer::Renderer(const Scene& scene)
    : scene_(scene), accel_(std::make_unique<Accel>(scene)), lights_(std::make_unique<Lights>(scene, *accel_)) {}

Renderer::~Renderer() = default;

RenderStats Renderer::render(Film& film, const RenderOptions& opt) const {
  const auto t0 = std::chrono::steady_clock::now();
  const RenderSettings& rs = scene_.render;
  const int W = film.width(), H = film.height();
  const Mode mode = mode_of(rs.integrator);
  const RenderContext ctx{scene_, *accel_, *lights_, rs.max_depth};
  const std::unique_ptr<Integrator> integrator =
      mode == Mode::Radiance ? make_integrator(rs.integrator, ctx) : nullptr;
  const SamplerKind sk = sampler_kind(rs.sampler);
  const bool gaussian = rs.filter == "gaussian";
  const auto spp = uint32_t(rs.spp);
  const bool want_aovs = !opt.aovs.empty() || mode != Mode::Radiance;
  // Differentials of one sample's share of a pixel: rays of many samples cover less each.
  const double fp_scale = std::max(0.125, 1.0 / std::sqrt(double(spp)));
  const double du = fp_scale / W, dv = fp_scale / H;

  std::vector<Tile> tiles;
  const int ts = rs.tile_size;
  for (int y = 0; y < H; y += ts)
    for (int x = 0; x < W; x += ts) tiles.push_back({x, y, std::min(x + ts, W), std::min(y + ts, H)});

  // Progressive passes: 1, 1, 2, 4, ... samples per pixel until spp.
  std::vector<uint32_t> pass_end;
  if (opt.progressive) {
    uint32_t done = 0, step = 1;
    while (done < spp) {
      done = std::min(spp, done + step);
      pass_end.push_back(done);
      if (pass_end.size() > 1) step *= 2;
    }
  } else {
    pass_end.push_back(spp);
  }

  RenderStats stats;
  std::mutex mu;
  uint64_t samples_done = 0, rays_done = 0;
  const uint64_t samples_total = uint64_t(W) * H * spp;
  tbb::task_arena arena(opt.threads > 0 ? opt.threads : tbb::task_arena::automatic);

  uint32_t s_begin = 0;
  for (size_t pass = 0; pass < pass_end.size(); ++pass) {
    const uint32_t s_end = pass_end[pass];
    std::vector<TileStats> tile_stats(tiles.size());
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<size_t>(0, tiles.size(), 1), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t ti = range.begin(); ti != range.end(); ++ti) {
          if (opt.cancel && opt.cancel->load(std::memory_order_relaxed)) return;
          const Tile& t = tiles[ti];
          TileStats& st = tile_stats[ti];
          for (uint32_t s = s_begin; s < s_end; ++s) {
            // Coherent packets of 4x4 pixels for the primary rays.
            constexpr int kPacket = 16;
            for (int y = t.y0; y < t.y1; y += 4)
              for (int x = t.x0; x < t.x1; x += 4) {
                Ray rays[kPacket];
                CameraRay cam[kPacket];
                bool valid[kPacket], found[kPacket];
                Hit hits[kPacket];
                Rng rng[kPacket];
                int lx[kPacket], ly[kPacket];
                for (int k = 0; k < kPacket; ++k) {
                  lx[k] = x + (k & 3);
                  ly[k] = y + (k >> 2);
                  valid[k] = false;
                  if (lx[k] >= t.x1 || ly[k] >= t.y1) continue;
                  rng[k] = Rng::for_sample(uint32_t(lx[k]), uint32_t(ly[k]), s, rs.seed);
                  const uint32_t key = uint32_t(mix64((uint64_t(ly[k]) << 32 | uint32_t(lx[k])) ^ rs.seed));
                  Vec2 off = pixel_offset(sk, s, spp, key, rng[k]);
                  if (gaussian) off = gaussian_offset(off, rs.filter_radius) + Vec2{0.5, 0.5};
                  CameraSample cs;
                  cs.uv = {std::clamp((lx[k] + off.x) / W, 0.0, 1.0), std::clamp((ly[k] + off.y) / H, 0.0, 1.0)};
                  cs.lens = {rng[k].uniform(), rng[k].uniform()};
                  auto r = scene_.camera->generate(cs);
                  if (!r) continue;
                  cam[k] = *r;
                  rays[k] = Ray{r->org, r->dir, 0, kInf};
                  valid[k] = true;
                }
                accel_->intersect16(rays, valid, hits, found);
                for (int k = 0; k < kPacket; ++k) {
                  if (lx[k] >= t.x1 || ly[k] >= t.y1) continue;
                  AovSample a;
                  if (!valid[k]) {
                    film.add(lx[k], ly[k], {}, 0, a, s == 0);  // no ray: transparent
                    st.samples++;
                    continue;
                  }
                  st.rays++;
                  Footprint fp;
                  if (found[k]) fp = footprint_at(cam[k], du, dv, hits[k]);
                  if (want_aovs && found[k]) {
                    const Hit& h = hits[k];
                    const Material& m = scene_.materials[h.material];
                    a.hit = true;
                    a.albedo = m.base_color.eval(texcoord_at(h, fp));
                    a.normal = dot(h.ns, cam[k].dir) > 0 ? -h.ns : h.ns;
                    a.position = h.p;
                    a.depth = h.t;  // distance along the camera ray from its origin (dir is unit)
                    a.id = h.object_id;
                    a.uv = h.uv;
                  }
                  Color L = mode == Mode::Radiance
                                ? integrator->radiance(rays[k], found[k] ? &hits[k] : nullptr, fp, rng[k], st.rays)
                                : aov_beauty(mode, a);
                  st.samples++;
                  if (!is_finite(L)) {
                    if (st.nans++ == 0) st.nan_x = lx[k], st.nan_y = ly[k], st.nan_s = int(s);
                    continue;  // dropped
                  }
                  film.add(lx[k], ly[k], L, 1, a, s == 0);
                }
              }
          }
          if (opt.on_progress) {
            std::lock_guard<std::mutex> lock(mu);
            samples_done += uint64_t(t.x1 - t.x0) * (t.y1 - t.y0) * (s_end - s_begin);
            rays_done += st.rays;
            Progress p;
            p.fraction = double(samples_done) / double(samples_total);
            p.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            p.rays = rays_done;
            p.pass = int(pass);
            p.passes = int(pass_end.size());
            opt.on_progress(p);
          }
        }
      }, tbb::simple_partitioner());
    });
    for (const TileStats& st : tile_stats) {
      stats.rays += st.rays;
      stats.samples += st.samples;
      if (st.nans) {
        // Keep the first in (y, x, sample) order so reports do not depend on scheduling.
        const bool earlier = stats.nan_samples == 0 || st.nan_y < stats.nan_y ||
                             (st.nan_y == stats.nan_y && (st.nan_x < stats.nan_x ||
                                                          (st.nan_x == stats.nan_x && st.nan_s < stats.nan_sample)));
        if (earlier) stats.nan_x = st.nan_x, stats.nan_y = st.nan_y, stats.nan_sample = st.nan_s;
        stats.nan_samples += st.nans;
      }
    }
    if (opt.cancel && opt.cancel->load()) {
      stats.cancelled = true;
      break;
    }
    if (opt.on_pass) opt.on_pass(film, int(pass));
    s_begin = s_end;
  }
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return stats;
}

}  // namespace anamorph
