#include "render/renderer.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>

#include "accel/accel.h"
#include "math/parallel.h"
#include "render/lights.h"
#include "render/render_job.h"
#include "render/tile_farm.h"
#include "render/tile_session.h"

namespace anamorph {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

bool is_set(const std::atomic<bool>* flag) { return flag && flag->load(std::memory_order_relaxed); }

// Passes of a pass render: progressive 1, 1, 2, 4, ... samples per pixel; per-pixel adaptive
// sampling the same schedule from min_spp on. Each entry is the sample count after the pass.
std::vector<uint32_t> pass_ends(uint32_t spp, uint32_t first, bool progressive) {
  if (!progressive) return {spp};
  std::vector<uint32_t> ends;
  for (uint32_t done = 0, step = first; done < spp;) {
    done = std::min(spp, done + step);
    ends.push_back(done);
    if (ends.size() > 1) step *= 2;
  }
  return ends;
}

}  // namespace

// Everything one render call shares: the job, the threads, progress and statistics.
struct Renderer::Run {
  Run(const Renderer& r, const RenderOptions& o, int W, int H)
      : opt(o),
        session(local_session(r, o, W, H)),
        arena(arena_concurrency(o.threads)),
        time_limit(r.scene_.render.time_limit) {}

  // The tiles' shared state, for rendering here (none when a farm renders them).
  static std::unique_ptr<const TileSession> local_session(const Renderer& r, const RenderOptions& o,
                                                          int W, int H) {
    if (o.farm) return nullptr;
    if (!r.accel_) throw std::logic_error("this renderer hands all its tiles to a farm");
    return std::make_unique<const TileSession>(r, !o.aovs.empty(), W, H, o.cancel);
  }

  const RenderOptions& opt;
  const std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
  const std::unique_ptr<const TileSession> session;
  tbb::task_arena arena;
  const double time_limit;
  std::atomic<size_t> started{0};
  std::atomic<bool> out_of_time{false};
  std::mutex mu;
  uint64_t work_done = 0, rays_done = 0, work_total = 1;
  uint32_t pass_samples = 0;  // samples per pixel of the pass running (0: whole tiles)
  RenderStats stats;

  bool cancelled() const { return is_set(opt.cancel); }

  // render.time_limit: whether another tile may start. The first tile of a run always may, so a
  // resumed render always gets further.
  bool may_start_tile() {
    if (past_time_limit()) {
      out_of_time.store(true, std::memory_order_relaxed);
      return false;
    }
    started.fetch_add(1, std::memory_order_relaxed);
    return true;
  }
  bool past_time_limit() const {
    return time_limit > 0 && started.load() > 0 && seconds_since(t0) > time_limit;
  }

  // A tile's work is done: its statistics into the render's, progress to the caller.
  void tile_done(const TileStats& st, uint64_t work, int pass, int passes) {
    const std::lock_guard<std::mutex> lock(mu);
    merge(st);
    work_done += work;
    rays_done += st.rays;
    if (!opt.on_progress) return;
    Progress p;
    p.fraction = std::min(1.0, double(work_done) / double(std::max<uint64_t>(1, work_total)));
    p.seconds = seconds_since(t0);
    p.rays = rays_done;
    p.pass = pass;
    p.passes = passes;
    opt.on_progress(p);
  }

  // A tile's cost, for --stats. `begin`: when it started.
  void record_time(size_t index, int pass, std::chrono::steady_clock::time_point begin,
                   const TileStats& st) {
    if (!opt.tile_times) return;
    const auto end = std::chrono::steady_clock::now();
    record_time(index, pass, std::chrono::duration<double>(end - begin).count(), st);
  }
  // A tile rendered elsewhere (a farm), which took `seconds` there and has just come back.
  void record_time(size_t index, int pass, double seconds, const TileStats& st, int rank = 0) {
    if (!opt.tile_times) return;
    TileTiming t;
    t.rank = rank;
    t.pass_samples = pass_samples;
    t.index = index;
    t.pass = pass;
    t.start = std::max(0.0, seconds_since(t0) - seconds);
    t.seconds = seconds;
    t.samples = st.samples;
    t.rays = st.rays;
    const std::lock_guard<std::mutex> lock(mu);
    opt.tile_times->push_back(t);
  }

  void merge(const TileStats& st) {
    stats.rays += st.rays;
    stats.samples += st.samples;
    if (!st.nans) return;
    // Keep the first in (y, x, sample) order so reports do not depend on scheduling.
    const bool earlier =
        stats.nan_samples == 0 || st.nan_y < stats.nan_y ||
        (st.nan_y == stats.nan_y &&
         (st.nan_x < stats.nan_x || (st.nan_x == stats.nan_x && st.nan_s < stats.nan_sample)));
    if (earlier) stats.nan_x = st.nan_x, stats.nan_y = st.nan_y, stats.nan_sample = st.nan_s;
    stats.nan_samples += st.nans;
  }

  RenderStats finish() {
    stats.seconds = seconds_since(t0);
    return stats;
  }
};

Renderer::Renderer(const Scene& scene)
    : scene_(scene),
      accel_(std::make_unique<Accel>(scene)),
      lights_(std::make_unique<Lights>(scene, *accel_)) {}

Renderer::Renderer(const Scene& scene, FarmOnly) : scene_(scene) {}

Renderer::~Renderer() = default;

bool Renderer::streams(const RenderSettings& rs) {
  return !(rs.adaptive() && rs.antialias == Antialias::Pixel);
}

RenderStats Renderer::render_tiles(const TileGrid& grid, const RenderOptions& opt,
                                   const std::vector<uint8_t>& skip, const TileSink& sink) const {
  return whole_tiles(grid, opt, skip, false, false, sink, nullptr);
}

RenderStats Renderer::render_resolved(const TileGrid& grid, const RenderOptions& opt,
                                      const std::vector<uint8_t>& skip, bool png, bool exr,
                                      const std::function<void(ResolvedTile&&)>& sink) const {
  return whole_tiles(
      grid, opt, skip, png, exr,
      [&](size_t i, std::unique_ptr<TileBuffer>& t) { sink(resolve(i, *t, png, exr)); }, sink);
}

RenderStats Renderer::whole_tiles(const TileGrid& grid, const RenderOptions& opt,
                                  const std::vector<uint8_t>& skip, bool png, bool exr,
                                  const TileSink& sink,
                                  const std::function<void(ResolvedTile&&)>& resolved) const {
  Run run(*this, opt, grid.width, grid.height);
  const uint64_t per_pixel = TileSession::whole_work_per_pixel(scene_.render);
  run.work_total = uint64_t(grid.width) * uint64_t(grid.height) * per_pixel;
  const auto skipped = [&](size_t ti) { return ti < skip.size() && skip[ti]; };
  for (size_t i = 0; i < grid.count(); ++i)
    if (skipped(i)) run.work_done += grid.rect(i).pixels() * per_pixel;

  if (opt.farm) {
    size_t ti = 0;
    opt.farm->run(
        [&]() -> std::optional<FarmTile> {
          while (ti < grid.count() && skipped(ti)) ++ti;
          if (ti == grid.count() || run.cancelled() || !run.may_start_tile()) return {};
          const size_t i = ti++;
          FarmTile t;
          t.index = i;
          t.rect = grid.rect(i);
          t.png = png;
          t.exr = exr;
          return t;
        },
        [&](FarmResult& r) {
          run.record_time(r.index, 0, r.seconds, r.stats, r.rank);
          run.tile_done(r.stats, grid.rect(r.index).pixels() * per_pixel, 0, 1);
          if (run.cancelled()) return;
          if (r.resolved)
            resolved(std::move(*r.resolved));
          else
            sink(r.index, r.tile);
        });
  } else {
    tbb::enumerable_thread_specific<std::unique_ptr<TileBuffer>> spare;  // tiles the sink left
    run.arena.execute([&] {
      parallel_in_order(0, grid.count(), [&](size_t ti) {
        if (skipped(ti) || run.cancelled() || !run.may_start_tile()) return;
        std::unique_ptr<TileBuffer>& tile = spare.local();
        if (tile)
          tile->reset(grid.rect(ti));
        else
          tile = std::make_unique<TileBuffer>(grid.rect(ti), opt.aovs);
        TileStats st;
        const auto begin = std::chrono::steady_clock::now();
        run.session->whole(*tile, st);
        run.record_time(ti, 0, begin, st);
        run.tile_done(st, tile->rect().pixels() * per_pixel, 0, 1);
        if (!run.cancelled()) sink(ti, tile);
      });
    });
  }
  run.stats.cancelled = run.cancelled();
  run.stats.time_limited = run.out_of_time;
  return run.finish();
}

RenderStats Renderer::render(Film& film, const RenderOptions& opt) const {
  const RenderSettings& rs = scene_.render;
  const bool per_pixel = !streams(rs);
  if (!per_pixel && (!opt.progressive || rs.adaptive())) {
    // One pass: each tile complete, straight into the film.
    film.clear();
    RenderStats st = render_tiles(
        film.grid(), opt, {},
        [&](size_t i, std::unique_ptr<TileBuffer>& tile) { film.put(i, std::move(tile)); });
    if (!st.cancelled && !st.time_limited && opt.on_pass) opt.on_pass(film, 0);
    return st;
  }
  return render_passes(film, opt);
}

RenderStats Renderer::render_passes(Film& film, const RenderOptions& opt) const {
  const RenderSettings& rs = scene_.render;
  Run run(*this, opt, film.width(), film.height());
  const TileGrid& grid = film.grid();
  const bool per_pixel = !streams(rs);
  // Whitted's samples of a pixel differ only by where they fall in it (a deterministic
  // integrand, whose scrambled-Sobol' estimate converges faster than noise): its own rule.
  const StopRule stop_rule = rs.integrator == IntegratorKind::Whitted
                                 ? StopRule::deterministic(rs.noise_threshold)
                                 : StopRule::noisy(rs.noise_threshold);
  const auto spp = uint32_t(per_pixel ? rs.max_spp : rs.spp);
  const std::vector<uint32_t> ends =
      pass_ends(spp, per_pixel ? uint32_t(rs.min_spp) : 1, opt.progressive || per_pixel);
  run.work_total = uint64_t(film.width()) * uint64_t(film.height()) * spp;
  // Which pixels still take samples (per-pixel adaptive sampling only; empty means all of them).
  std::vector<uint8_t> active;
  if (per_pixel) active.assign(size_t(film.width()) * size_t(film.height()), 1);
  const PassResume* resume = opt.resume;
  run.stats.passes = int(ends.size());
  size_t first = 0;
  if (resume) {
    first = size_t(resume->pass);
    if (per_pixel) active = resume->active;
  } else {
    film.clear();
  }

  for (size_t pass = first; pass < ends.size(); ++pass) {
    const uint32_t s_begin = pass ? ends[pass - 1] : 0, s_end = ends[pass];
    if (opt.on_pass_start) opt.on_pass_start(int(pass), active);
    // Texture footprints: with per-pixel adaptive sampling a pixel that takes this pass's samples
    // ends with at least s_end of them, and each sample stands for that share of the pixel (a
    // function of the sample index alone, so tiles and threads agree).
    const SampleRange range{s_begin, s_end,
                            RenderJob::footprint_scale(per_pixel ? s_end : uint32_t(rs.spp)),
                            per_pixel ? &active : nullptr};
    const bool resumed_pass = resume && pass == first;
    const int passes = int(ends.size());
    run.pass_samples = s_end - s_begin;
    // Tiles the checkpoint holds after this pass already count as done.
    const auto done_before = [&](size_t ti) {
      if (!resumed_pass || resume->tile_pass[ti] < int(pass)) return false;
      run.tile_done({}, grid.rect(ti).pixels() * (s_end - s_begin), int(pass), passes);
      return true;
    };
    const auto tile_back = [&](size_t ti, const TileStats& st) {
      run.tile_done(st, grid.rect(ti).pixels() * (s_end - s_begin), int(pass), passes);
      if (!run.cancelled() && opt.on_tile_pass) opt.on_tile_pass(ti, int(pass), film.tile(ti));
    };
    if (opt.farm) {
      // Tiles with no pixel left to sample are done here: nothing to send.
      const auto idle = [&](size_t ti) {
        if (!per_pixel) return false;
        const TileRect r = grid.rect(ti);
        for (int y = r.y0; y < r.y1; ++y)
          for (int x = r.x0; x < r.x1; ++x)
            if (active[size_t(y) * size_t(grid.width) + size_t(x)]) return false;
        tile_back(ti, {});
        return true;
      };
      size_t ti = 0;
      opt.farm->run(
          [&]() -> std::optional<FarmTile> {
            while (ti < grid.count() && !run.cancelled() && (done_before(ti) || idle(ti))) ++ti;
            if (ti == grid.count() || run.cancelled() || !run.may_start_tile()) return {};
            const size_t i = ti++;
            return FarmTile{i, grid.rect(i), grid.width, false, range, &film.tile(i)};  // a pass
          },
          [&](FarmResult& r) {
            run.record_time(r.index, int(pass), r.seconds, r.stats, r.rank);
            tile_back(r.index, r.stats);
          });
    } else {
      run.arena.execute([&] {
        parallel_in_order(0, grid.count(), [&](size_t ti) {
          if (run.cancelled() || done_before(ti) || !run.may_start_tile()) return;
          TileStats st;
          const auto begin = std::chrono::steady_clock::now();
          run.session->samples(range, film.tile(ti), st);
          run.record_time(ti, int(pass), begin, st);
          tile_back(ti, st);
        });
      });
    }
    run.stats.pass = int(pass);
    if (run.cancelled()) {
      run.stats.cancelled = true;
      break;
    }
    if (run.out_of_time) {  // tiles of this pass left out
      run.stats.time_limited = true;
      break;
    }
    if (opt.on_pass) opt.on_pass(film, int(pass));
    if (per_pixel) {
      size_t still_active = 0;
      run.arena.execute([&] { still_active = update_active(film, stop_rule, &active); });
      if (still_active == 0) break;
    }
    if (pass + 1 < ends.size() && run.past_time_limit()) {  // the next pass starts when resumed
      run.stats.time_limited = true;
      run.stats.pass = int(pass) + 1;
      break;
    }
  }
  return run.finish();
}

}  // namespace anamorph
