// One frame of `anamorph render`: rendered into its output files (app/frame_job.h; with the coin
// overlay, coin_overlay.cpp), then its tile costs, its summary and what an interruption or a time
// limit left.
#include <fmt/format.h>
#include <unistd.h>

#include <thread>

#include "app/frame_job.h"
#include "app/interrupt.h"
#include "app/output_guard.h"
#include "app/render_command.h"
#include "app/tile_stats.h"
#include "dist/head.h"
#include "io/image_sink.h"
#include "render/denoise_film.h"
#include "render/frame_output.h"
#include "render/memory_estimate.h"

namespace anamorph::app {

namespace fs = std::filesystem;

namespace {

// Says where the image so far and the finished tiles are; kInterrupted.
int interrupted(const RenderSetup& s, const FrameFiles& files, const FrameJob& job) {
  const fs::path partial = FrameOutput::with_suffix(job.files[0], ".partial");
  const std::string& ck = files.checkpoint;
  fmt::print(stderr, "interrupted: {} not written; the image so far is in {}{}\n", files.out,
             partial.string(),
             ck.empty() ? ""
             : s.farm   ? fmt::format("; the finished tiles are in {}: run the same mpirun "
                                        "command again to resume",
                                      ck)
                        : fmt::format("; resume with: anamorph render --resume {}", ck));
  return kInterrupted;
}

// The frame streamed into its files (FrameJob); returns an exit code.
int render_to_outputs(const RenderSetup& s, const Scene& scene, const Renderer& renderer,
                      double frame, const FrameFiles& files,
                      const std::function<void(const Progress&)>& on_progress,
                      std::vector<TileTiming>* tile_times, bool bar, RenderStats* st) {
  FrameJob job{scene,
               renderer,
               s.aovs,
               output_files(files.out, render_layers(s.aovs)),
               frame_metadata(scene, frame, s.aovs),
               files.checkpoint,
               s.checkpoint_every,
               s.args.threads.value_or(0),
               on_progress,
               tile_times,
               s.farm};
  job.denoise = s.args.denoise;
  FrameResult r;
  {
    const RenderPhase phase;
    r = render_to_files(job);
  }
  if (bar) clear_progress();
  *st = r.stats;
  const bool quiet = s.args.quiet;
  if (r.resumed && !quiet)
    fmt::print(messages(), "resumed from {}: {} tiles were done\n", files.checkpoint,
               r.resumed_tiles);
  if (r.interrupted) return interrupted(s, files, job);
  // (AOVs a PNG cannot hold go beside it, with the beauty, into an EXR of the same name.)
  if (job.files.size() > 1 && !quiet)
    fmt::print(messages(), "AOVs written to {}\n", job.files[1].string());
  if (r.denoise_seconds > 0 && !quiet)
    fmt::print(messages(), "denoised in {:.2f} s\n", r.denoise_seconds);
  if (r.time_limited && !quiet)
    fmt::print(messages(), "{}: time limit of {} s reached after {}; {}\n", files.out,
               scene.render.time_limit, r.reached,
               files.checkpoint.empty()
                   ? "render with --checkpoint FILE to be able to continue"
                   : fmt::format("continue with: anamorph render --resume {}", files.checkpoint));
  return kOk;
}

// The coin overlay's frame, kept in a film; returns an exit code.
int render_overlay_frame(const RenderSetup& s, const Scene& scene, const Renderer& renderer,
                         double frame, const FrameFiles& files,
                         const std::function<void(const Progress&)>& on_progress,
                         std::vector<TileTiming>* tile_times, RenderStats* st) {
  RenderOptions opt;
  opt.threads = s.args.threads.value_or(0);
  opt.aovs = s.aovs;
  opt.cancel = &interrupt_flag();
  opt.on_progress = on_progress;
  opt.farm = s.farm;
  opt.tile_times = tile_times;
  return render_with_overlay(s, scene, renderer, frame, files.out, opt, st);
}

}  // namespace

int render_frame(const RenderSetup& s, const Scene& scene, const Renderer& renderer, double frame,
                 const FrameFiles& files, const std::string& prefix, const JobPlace& place) {
  const bool bar = !s.args.quiet && isatty(STDERR_FILENO);
  const auto on_progress = progress_printer(s, prefix, place, bar);
  RenderStats st;
  std::vector<TileTiming> tile_times;
  std::vector<TileTiming>* times = files.stats.empty() ? nullptr : &tile_times;
  int rc = kOk;
  if (s.args.coins_overlay) {
    rc = render_overlay_frame(s, scene, renderer, frame, files, on_progress, times, &st);
    if (bar) clear_progress();
  } else {
    rc = render_to_outputs(s, scene, renderer, frame, files, on_progress, times, bar, &st);
  }
  if (rc != kOk) return rc;
  if (!files.stats.empty()) {
    set_interrupt_note(fmt::format("{} not written ({} was)", files.stats, files.out));
    write_tile_stats(files.stats, scene, frame, s.args.threads.value_or(0), st,
                     std::move(tile_times));
    if (!s.args.quiet) fmt::print(messages(), "tile costs written to {}\n", files.stats);
  }
  print_summary(s, files.out, scene, st);
  return kOk;
}

bool denoise_applies(const RenderSetup& s, const Scene& scene, const std::string& out) {
  if (!s.args.denoise) return true;
  const auto why = denoise_unsupported(scene.render);
  if (why) print_error(fmt::format("{}: --denoise: {}", out, *why));
  return !why;
}

bool fits_in_memory(const RenderSetup& s, const Scene& scene, const std::string& out) {
  const RenderSettings& rs = scene.render;
  const RenderArgs& a = s.args;
  RenderShape shape;
  shape.width = rs.width;
  shape.height = rs.height;
  shape.tile_size = rs.tile_size;
  shape.threads = a.threads.value_or(0) > 0 ? *a.threads : int(std::thread::hardware_concurrency());
  shape.denoise = a.denoise;
  shape.aov_floats = aov_floats(a.denoise ? with_denoise_aovs(s.aovs) : s.aovs);
  shape.whole_film = a.coins_overlay || renders_in_passes(rs);
  shape.active_mask = !Renderer::streams(rs);
  const std::vector<LayerSpec> layers = render_layers(s.aovs);
  shape.strip_bytes_per_pixel = strip_bytes_per_pixel(output_files(out, layers), layers);
  shape.output_image = a.coins_overlay;
  const auto shortfall = memory_shortfall(estimate_render_memory(scene, shape));
  if (!shortfall) return true;
  print_error(fmt::format("{}: {}; lower the resolution or the AOVs{}", out, *shortfall,
                          shape.whole_film && !a.coins_overlay
                              ? ", or sample uniformly without a time limit (render.antialias = "
                                "\"uniform\" streams tiles to the file instead of keeping the "
                                "frame)"
                              : ""));
  return false;
}

}  // namespace anamorph::app
