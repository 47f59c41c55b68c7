#include "render/renderer.h"

#include <algorithm>
#include <stdexcept>

#include "accel/accel.h"
#include "render/lights.h"
#include "render/render_job.h"
#include "render/render_run.h"
#include "render/tile_session.h"

namespace anamorph {

namespace {

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

// Every tile with all its samples, each handed to a sink as it comes back: resolved where it was
// rendered to the outputs' plan when there is one, else as its sums.
class WholeTiles final : public TileWork {
 public:
  WholeTiles(RenderRun& run, const TileGrid& grid, const std::vector<uint8_t>& skip,
             uint64_t per_pixel, const std::vector<LayerRequest>* plan, const TileSink& sink,
             const std::function<void(ResolvedTile&&)>& resolved)
      : run_(run),
        grid_(grid),
        skip_(skip),
        per_pixel_(per_pixel),
        plan_(plan),
        sink_(sink),
        resolved_(resolved) {}
  size_t count() const override { return grid_.count(); }
  bool settled(size_t i) override { return i < skip_.size() && skip_[i]; }
  FarmTile request(size_t i) override {
    FarmTile t;
    t.index = i;
    t.rect = grid_.rect(i);
    t.plan = plan_;
    return t;
  }
  void back(FarmResult& r) override {
    run_.tile_done(r.stats, grid_.rect(r.index).pixels() * per_pixel_, 0, 1);
    if (run_.cancelled()) return;
    if (r.resolved)
      resolved_(std::move(*r.resolved));
    else
      sink_(r.index, r.tile);
  }

 private:
  RenderRun& run_;
  const TileGrid& grid_;
  const std::vector<uint8_t>& skip_;
  const uint64_t per_pixel_;
  const std::vector<LayerRequest>* plan_;
  const TileSink& sink_;
  const std::function<void(ResolvedTile&&)>& resolved_;
};

// One pass of a pass render: the range's samples added to each tile's sums in the film.
class PassTiles final : public TileWork {
 public:
  PassTiles(RenderRun& run, Film& film, const SampleRange& range, int pass, int passes,
            const PassResume* resumed)
      : run_(run), film_(film), grid_(film.grid()), range_(range), resumed_(resumed) {
    this->pass = pass;
    this->passes = passes;
  }
  size_t count() const override { return grid_.count(); }
  // Tiles the checkpoint holds after this pass count as done; so do tiles with no pixel left to
  // sample (nothing to render or send).
  bool settled(size_t i) override {
    if (resumed_ && resumed_->tile_pass[i] >= pass) {
      run_.tile_done({}, work(i), pass, passes);
      return true;
    }
    if (!range_.active || any_active(i)) return false;
    tile_back(i, {});
    return true;
  }
  FarmTile request(size_t i) override {
    return FarmTile{i, grid_.rect(i), grid_.width, false, range_, &film_.tile(i)};
  }
  void back(FarmResult& r) override { tile_back(r.index, r.stats); }

 private:
  uint64_t work(size_t i) const { return grid_.rect(i).pixels() * (range_.end - range_.begin); }
  bool any_active(size_t i) const {
    const TileRect r = grid_.rect(i);
    for (int y = r.y0; y < r.y1; ++y)
      for (int x = r.x0; x < r.x1; ++x)
        if ((*range_.active)[size_t(y) * size_t(grid_.width) + size_t(x)]) return true;
    return false;
  }
  void tile_back(size_t i, const TileStats& st) {
    run_.tile_done(st, work(i), pass, passes);
    if (!run_.cancelled() && run_.opt.on_tile_pass) run_.opt.on_tile_pass(i, pass, film_.tile(i));
  }
  RenderRun& run_;
  Film& film_;
  const TileGrid& grid_;
  const SampleRange range_;
  const PassResume* resumed_;  // the pass a resumed render continues, or null
};

// A pass render's schedule and state across passes: which pixels still take samples (per-pixel
// adaptive sampling), where a resumed render continues, when to stop.
class PassSchedule {
 public:
  PassSchedule(const RenderSettings& rs, const RenderOptions& opt, const Film& film)
      : per_pixel_(!Renderer::streams(rs)),
        spp_(uint32_t(per_pixel_ ? rs.max_spp : rs.spp)),
        ends_(opt.split_at > 0 && !per_pixel_ && opt.split_at < spp_
                  ? std::vector<uint32_t>{opt.split_at, spp_}
                  : pass_ends(spp_, per_pixel_ ? uint32_t(rs.min_spp) : 1,
                              opt.progressive || per_pixel_)),
        uniform_spp_(opt.finest_footprint ? ~0u : uint32_t(rs.spp)),
        // Whitted's samples of a pixel differ only by where they fall in it (a deterministic
        // integrand, whose scrambled-Sobol' estimate converges faster than noise): its own rule.
        stop_rule_(rs.deterministic() ? StopRule::deterministic(rs.noise_threshold)
                                      : StopRule::noisy(rs.noise_threshold)),
        resume_(opt.resume) {
    if (per_pixel_) active_.assign(size_t(film.width()) * size_t(film.height()), 1);
    if (resume_ && per_pixel_) active_ = resume_->active;
  }
  size_t first() const { return resume_ ? size_t(resume_->pass) : 0; }
  size_t passes() const { return ends_.size(); }
  uint64_t samples_per_pixel() const { return spp_; }
  const std::vector<uint8_t>& active() const { return active_; }
  // Texture footprints: with per-pixel adaptive sampling a pixel that takes this pass's samples
  // ends with at least its end count of them, and each sample stands for that share of the pixel
  // (a function of the sample index alone, so tiles and threads agree).
  SampleRange range(size_t pass) const {
    const uint32_t s_begin = pass ? ends_[pass - 1] : 0, s_end = ends_[pass];
    return {s_begin, s_end, RenderJob::footprint_scale(per_pixel_ ? s_end : uniform_spp_),
            per_pixel_ ? &active_ : nullptr};
  }
  const PassResume* resumed(size_t pass) const {
    return resume_ && pass == first() ? resume_ : nullptr;
  }
  // After a pass: whether any pixel still takes samples (always, without per-pixel adaptive
  // sampling).
  bool update(const Film& film, tbb::task_arena& arena) {
    if (!per_pixel_) return true;
    size_t still_active = 0;
    arena.execute([&] { still_active = update_active(film, stop_rule_, &active_); });
    return still_active > 0;
  }

 private:
  const bool per_pixel_;
  const uint32_t spp_;
  const std::vector<uint32_t> ends_;
  const uint32_t uniform_spp_;
  const StopRule stop_rule_;
  const PassResume* resume_;
  std::vector<uint8_t> active_;  // per-pixel adaptive sampling only; empty means all pixels
};

}  // namespace

Renderer::Renderer(const Scene& scene)
    : scene_(scene),
      accel_(std::make_unique<Accel>(scene)),
      lights_(std::make_unique<Lights>(scene, *accel_)) {}

Renderer::Renderer(const Scene& scene, FarmOnly) : scene_(scene) {}

void Renderer::repose() {
  if (!accel_) return;
  lights_.reset();  // (it refers to the acceleration structure)
  if (!accel_->repose(scene_)) {
    accel_.reset();
    accel_ = std::make_unique<Accel>(scene_);
  }
  lights_ = std::make_unique<Lights>(scene_, *accel_);
}

Renderer::~Renderer() = default;

bool Renderer::streams(const RenderSettings& rs) {
  return !(rs.adaptive() && rs.antialias == Antialias::Pixel);
}

std::unique_ptr<TileSession> Renderer::session(std::vector<Aov> aovs, int width, int height,
                                               const std::atomic<bool>* cancel,
                                               const RenderSettings* settings) const {
  if (!accel_) throw std::logic_error("this renderer hands all its tiles to a farm");
  return std::make_unique<TileSession>(TileSession::World{scene_, *accel_, *lights_, settings},
                                       std::move(aovs), width, height, cancel);
}

namespace {

// The run of one render call: this process's threads render its tiles unless a farm does.
std::unique_ptr<RenderRun> start_run(const Renderer& r, const RenderOptions& opt, int width,
                                     int height) {
  std::unique_ptr<const TileSession> session;
  if (!opt.farm) session = r.session(opt.aovs, width, height, opt.cancel, opt.settings);
  return std::make_unique<RenderRun>(opt, std::move(session), r.settings(opt).time_limit);
}

}  // namespace

RenderStats Renderer::render_tiles(const TileGrid& grid, const RenderOptions& opt,
                                   const std::vector<uint8_t>& skip, const TileSink& sink) const {
  return whole_tiles(grid, opt, skip, nullptr, sink, nullptr);
}

RenderStats Renderer::render_resolved(const TileGrid& grid, const RenderOptions& opt,
                                      const std::vector<uint8_t>& skip,
                                      const std::vector<LayerRequest>& plan,
                                      const std::function<void(ResolvedTile&&)>& sink) const {
  return whole_tiles(grid, opt, skip, &plan, nullptr, sink);
}

RenderStats Renderer::whole_tiles(const TileGrid& grid, const RenderOptions& opt,
                                  const std::vector<uint8_t>& skip,
                                  const std::vector<LayerRequest>* plan, const TileSink& sink,
                                  const std::function<void(ResolvedTile&&)>& resolved) const {
  const std::unique_ptr<RenderRun> run = start_run(*this, opt, grid.width, grid.height);
  const uint64_t per_pixel = TileSession::whole_work_per_pixel(settings(opt));
  run->set_work_total(uint64_t(grid.width) * uint64_t(grid.height) * per_pixel);
  for (size_t i = 0; i < grid.count(); ++i)
    if (i < skip.size() && skip[i]) run->add_done_work(grid.rect(i).pixels() * per_pixel);
  WholeTiles work(*run, grid, skip, per_pixel, plan, sink, resolved);
  run->sweep(work);
  run->stats.cancelled = run->cancelled();
  run->stats.time_limited = run->out_of_time();
  return run->finish();
}

RenderStats Renderer::render(Film& film, const RenderOptions& opt) const {
  const RenderSettings& rs = settings(opt);
  const bool per_pixel = !streams(rs);
  const bool split = opt.split_at > 0 && !rs.adaptive() && opt.split_at < uint32_t(rs.spp);
  if (!per_pixel && !split && (!opt.progressive || rs.adaptive())) {
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

// Pass after pass over the film, each a sweep over the tiles; between passes the callback, the
// stopping rule of per-pixel adaptive sampling and the time budget.
RenderStats Renderer::render_passes(Film& film, const RenderOptions& opt) const {
  const std::unique_ptr<RenderRun> run = start_run(*this, opt, film.width(), film.height());
  PassSchedule schedule(settings(opt), opt, film);
  run->set_work_total(uint64_t(film.width()) * uint64_t(film.height()) *
                      schedule.samples_per_pixel());
  run->stats.passes = int(schedule.passes());
  if (!opt.resume) film.clear();
  for (size_t pass = schedule.first(); pass < schedule.passes(); ++pass) {
    if (opt.on_pass_start) opt.on_pass_start(int(pass), schedule.active());
    const SampleRange range = schedule.range(pass);
    run->pass_samples = range.end - range.begin;
    PassTiles work(*run, film, range, int(pass), int(schedule.passes()), schedule.resumed(pass));
    run->sweep(work);
    run->stats.pass = int(pass);
    if (run->cancelled()) {
      run->stats.cancelled = true;
      break;
    }
    if (run->out_of_time()) {  // tiles of this pass left out
      run->stats.time_limited = true;
      break;
    }
    if (opt.on_pass) opt.on_pass(film, int(pass));
    if (!schedule.update(film, run->arena)) break;
    if (pass + 1 < schedule.passes() && run->past_time_limit()) {  // the next pass starts later
      run->stats.time_limited = true;
      run->stats.pass = int(pass) + 1;
      break;
    }
  }
  return run->finish();
}

}  // namespace anamorph
