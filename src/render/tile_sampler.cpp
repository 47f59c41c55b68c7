#include "render/tile_sampler.h"

#include <algorithm>
#include <vector>

#include "render/sampler.h"

namespace anamorph {

TileSampler::TileSampler(const RenderJob& job)
    : job_(job),
      lens_time_(job.scene.camera->uses_lens_or_time() || job.accel.has_motion()),
      gaussian_(job.rs.filter == PixelFilter::Gaussian) {
  needs_rng_ = lens_time_ || job.rs.sampler != SamplerKind::Center ||
               (job.mode == RenderMode::Radiance && job.integrator->draws_random_numbers());
  // Any prefix of a pixel's Sobol' samples is well stratified, which per-pixel adaptive sampling
  // needs: a pixel may stop after any pass.
  qmc_ = needs_rng_ && job.rs.sampler == SamplerKind::Stratified;
  // Without random numbers (pixel centers) every sample sits at this offset in its pixel.
  fixed_offset_ = gaussian_ ? gaussian_offset({0.5, 0.5}, job.rs.filter_radius) + Vec2{0.5, 0.5}
                            : Vec2{0.5, 0.5};
}

bool TileSampler::lane_on(const SampleRange& r, const TileRect& t, int x, int y) const {
  return x < t.x1 && y < t.y1 && (!r.active || (*r.active)[size_t(y) * size_t(job_.W) + size_t(x)]);
}

void TileSampler::build_fixed(const SampleRange& r, const TileRect& t, int x, int y,
                              Packet& p) const {
  double uc[4], vr[4];
  for (int i = 0; i < 4; ++i) {
    uc[i] = std::clamp((x + i + fixed_offset_.x) / job_.W, 0.0, 1.0);
    vr[i] = std::clamp((y + i + fixed_offset_.y) / job_.H, 0.0, 1.0);
  }
  for (int k = 0; k < kPacket; ++k) {
    p.x[k] = x + (k & 3);
    p.y[k] = y + (k >> 2);
    p.use[k] = lane_on(r, t, p.x[k], p.y[k]);
    p.cs[k] = CameraSample{};
    if (p.use[k]) p.cs[k].uv = {uc[k & 3], vr[k >> 2]};
  }
}

void TileSampler::build_random(const SampleRange& r, const TileRect& t, int x, int y, uint32_t s,
                               Packet& p) const {
  for (int k = 0; k < kPacket; ++k) {
    p.x[k] = x + (k & 3);
    p.y[k] = y + (k >> 2);
    p.use[k] = lane_on(r, t, p.x[k], p.y[k]);
    fill_lane(p, k, s);
  }
}

void TileSampler::fill_lane(Packet& p, int k, uint32_t s) const {
  CameraSample& cs = p.cs[k];
  cs = CameraSample{};  // unused lanes get a harmless sample; their rays are masked out
  if (!p.use[k]) return;
  if (!needs_rng_) {
    cs.uv = {std::clamp((p.x[k] + fixed_offset_.x) / job_.W, 0.0, 1.0),
             std::clamp((p.y[k] + fixed_offset_.y) / job_.H, 0.0, 1.0)};
    return;
  }
  const uint64_t seed = job_.rs.seed;
  Rng& rng = p.rng[k];
  rng = Rng::for_sample(uint32_t(p.x[k]), uint32_t(p.y[k]), s, seed);
  // Stratified sampling takes every number of the sample (position, lens, time, every bounce's
  // light, BSDF and roulette numbers) from the pixel's scrambled Sobol' points.
  if (qmc_) rng.qmc(s, mix64((uint64_t(p.y[k]) << 32 | uint32_t(p.x[k])) ^ seed));
  Vec2 off;
  if (qmc_)
    rng.uniform2(off.x, off.y);
  else
    off = pixel_offset(job_.rs.sampler, rng);
  if (gaussian_) off = gaussian_offset(off, job_.rs.filter_radius) + Vec2{0.5, 0.5};
  cs.uv = {std::clamp((p.x[k] + off.x) / job_.W, 0.0, 1.0),
           std::clamp((p.y[k] + off.y) / job_.H, 0.0, 1.0)};
  if (lens_time_) {
    rng.uniform2(cs.lens.x, cs.lens.y);
    cs.time = rng.uniform();
  }
}

void TileSampler::trace(Packet& p, uint32_t s, double footprint, TileBuffer& tile,
                        TileStats& st) const {
  const CameraRayBatch& cam = p.cam;
  job_.scene.camera->generate_batch(p.cs, kPacket, &p.cam);
  for (int k = 0; k < kPacket; ++k) p.valid[k] = cam.valid[k] && p.use[k];
  double time[kPacket] = {};  // (where moving objects are: the ray's time in the shutter)
  if (job_.accel.has_motion())
    for (int k = 0; k < kPacket; ++k) time[k] = job_.scene.camera->shutter_time(p.cs[k]);
  job_.accel.intersect16(cam.org, cam.dir, p.valid, p.hits, p.found, job_.hit_surface, time);
  SampleResult& res = p.res;
  for (int k = 0; k < kPacket; ++k) {
    if (!p.use[k]) continue;
    st.samples++;
    if (!p.valid[k]) {
      tile.add(p.x[k], p.y[k], {}, 0, AovSample{});  // no ray: transparent
      continue;
    }
    st.rays++;
    job_.finish(
        Ray{cam.origin(k), cam.direction(k), 0, kInf, time[k]}, [&] { return cam.ray(k); },
        p.found[k] ? &p.hits[k] : nullptr, p.cs[k].uv, p.rng[k], st.rays, res, footprint);
    if (!film_storable(res.L)) {
      st.nan(p.x[k], p.y[k], int(s));  // dropped
      continue;
    }
    tile.add(p.x[k], p.y[k], res.L, res.alpha, res.aov);
  }
}

void TileSampler::sample(const SampleRange& r, TileBuffer& tile, TileStats& st) const {
  if (r.active) {
    sample_listed(r, tile, st);
    return;
  }
  const TileRect& t = tile.rect();
  Packet p;
  // Cancellation is checked for every packet, so a tile of a million samples per pixel (or of
  // deep ray trees) stops within one packet's time.
  const auto cancelled = [this] { return job_.cancelled(); };
  for (uint32_t s = r.begin; s < r.end && !cancelled(); ++s)
    for (int y = t.y0; y < t.y1 && !cancelled(); y += 4)
      for (int x = t.x0; x < t.x1 && !cancelled(); x += 4) {
        if (needs_rng_)
          build_random(r, t, x, y, s, p);
        else
          build_fixed(r, t, x, y, p);
        trace(p, s, r.footprint, tile, st);
      }
}

// Per-pixel adaptive sampling leaves a few pixels of a tile on after the first passes: traced in
// 4x4 blocks, most lanes of a packet would be off and cost as much as on. The pixels still on
// are listed in block order (neighbours stay in one packet) and packed 16 to a packet. Each
// pixel's samples still arrive in sample order, so its sums are the same bits.
void TileSampler::sample_listed(const SampleRange& r, TileBuffer& tile, TileStats& st) const {
  const TileRect& t = tile.rect();
  std::vector<int> xs, ys;
  for (int by = t.y0; by < t.y1; by += 4)
    for (int bx = t.x0; bx < t.x1; bx += 4)
      for (int k = 0; k < kPacket; ++k)
        if (lane_on(r, t, bx + (k & 3), by + (k >> 2))) {
          xs.push_back(bx + (k & 3));
          ys.push_back(by + (k >> 2));
        }
  Packet p;
  const size_t n = xs.size();
  for (uint32_t s = r.begin; s < r.end && !job_.cancelled(); ++s)
    for (size_t i = 0; i < n && !job_.cancelled(); i += kPacket) {
      for (int k = 0; k < kPacket; ++k) {
        const size_t j = i + size_t(k);
        p.use[k] = j < n;
        p.x[k] = p.use[k] ? xs[j] : t.x0;
        p.y[k] = p.use[k] ? ys[j] : t.y0;
        fill_lane(p, k, s);
      }
      trace(p, s, r.footprint, tile, st);
    }
}

}  // namespace anamorph
