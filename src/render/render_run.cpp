#include "render/render_run.h"

#include <algorithm>
#include <optional>

#include "math/parallel.h"
#include "render/local_threads.h"
#include "render/tile_session.h"

namespace anamorph {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

RenderRun::RenderRun(const RenderOptions& o, std::unique_ptr<const TileSession> session,
                     double time_limit)
    : opt(o),
      arena(arena_concurrency(o.threads)),
      session_(std::move(session)),
      local_(session_ ? std::make_unique<LocalThreads>(*session_, arena) : nullptr),
      time_limit_(time_limit) {}

RenderRun::~RenderRun() = default;

void RenderRun::sweep(TileWork& work) {
  TileFarm& place = opt.farm ? *opt.farm : *local_;
  std::mutex next_mu;
  size_t next = 0;
  place.run(
      [&]() -> std::optional<FarmTile> {
        size_t i = 0;
        {
          const std::lock_guard<std::mutex> lock(next_mu);
          while (next < work.count() && !cancelled() && work.settled(next)) ++next;
          if (next == work.count() || cancelled() || !may_start_tile()) return {};
          i = next++;
        }
        return work.request(i);
      },
      [&](FarmResult& r) {
        record_time(r.index, work.pass, r.seconds, r.stats, r.rank);
        work.back(r);
      });
}

// render.time_limit: whether another tile may start. The first tile of a run always may, so a
// resumed render always gets further.
bool RenderRun::may_start_tile() {
  if (past_time_limit()) {
    out_of_time_.store(true, std::memory_order_relaxed);
    return false;
  }
  started_.fetch_add(1, std::memory_order_relaxed);
  return true;
}

bool RenderRun::past_time_limit() const {
  return time_limit_ > 0 && started_.load() > 0 && seconds_since(t0_) > time_limit_;
}

void RenderRun::tile_done(const TileStats& st, uint64_t work, int pass, int passes) {
  const std::lock_guard<std::mutex> lock(mu_);
  merge(st);
  work_done_ += work;
  rays_done_ += st.rays;
  if (!opt.on_progress) return;
  Progress p;
  p.fraction = std::min(1.0, double(work_done_) / double(std::max<uint64_t>(1, work_total_)));
  p.seconds = seconds_since(t0_);
  p.rays = rays_done_;
  p.pass = pass;
  p.passes = passes;
  opt.on_progress(p);
}

// A tile's cost, for --stats: it took `seconds` where it was rendered (`rank`: 0 here) and has
// just come back.
void RenderRun::record_time(size_t index, int pass, double seconds, const TileStats& st, int rank) {
  if (!opt.tile_times) return;
  TileTiming t;
  t.rank = rank;
  t.pass_samples = pass_samples;
  t.index = index;
  t.pass = pass;
  t.start = std::max(0.0, seconds_since(t0_) - seconds);
  t.seconds = seconds;
  t.samples = st.samples;
  t.rays = st.rays;
  const std::lock_guard<std::mutex> lock(mu_);
  opt.tile_times->push_back(t);
}

void RenderRun::merge(const TileStats& st) {
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

RenderStats RenderRun::finish() {
  stats.seconds = seconds_since(t0_);
  return stats;
}

}  // namespace anamorph
