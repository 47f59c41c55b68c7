// `anamorph render`: render a scene (or a frame range of an animated scene) to PNG or EXR.
#include <fmt/format.h>
#include <fmt/printf.h>
#include <unistd.h>

#include <atomic>
#include <cctype>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <thread>
#include <tuple>

#include "app/common.h"
#include "app/frame_check.h"
#include "app/frame_job.h"
#include "app/frame_pattern.h"
#include "app/output_guard.h"
#include "app/render_outputs.h"
#include "app/resume_options.h"
#include "app/thread_option.h"
#include "app/tile_stats.h"
#include "app/video.h"
#include "dist/head.h"
#include "dist/worker.h"
#include "dist/world.h"
#include "io/image_io.h"
#include "render/coin_layer.h"
#include "render/frame_output.h"
#include "render/memory_estimate.h"
#include "render/renderer.h"
#include "scene/scene_loader.h"
#include "scene/scene_schema.h"

namespace anamorph::app {

namespace fs = std::filesystem;

namespace {

struct RenderArgs {
  SceneOptions scene;
  std::string output;
  std::optional<int> spp, threads;
  std::optional<int64_t> seed;
  std::optional<std::string> integrator, sampler;
  std::string aovs;
  std::string frames;  // "A:B" or "N"
  std::string video;
  int fps = 30;
  bool coins_overlay = false;  // --aov coins
  bool quiet = false;
  std::string checkpoint;  // --checkpoint FILE (a frame pattern with --frames)
  std::string checkpoint_every = "60s";
  std::string stats;          // --stats FILE (a frame pattern with --frames)
  std::string resume;         // --resume FILE
  ResumeOptions with_resume;  // the other options given with --resume
  bool skip_existing = false;
};

// "90", "90s", "5m", "2h" as seconds; false if malformed.
bool parse_duration(const std::string& text, double* seconds) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || !(v > 0) || v > 1e7) return false;
  const std::string unit = end;
  const double scale = unit.empty() || unit == "s" ? 1 : unit == "m" ? 60 : unit == "h" ? 3600 : 0;
  *seconds = v * scale;
  return scale > 0;
}

// Where a frame stands in its job: frame `index` (from 0) of `count`, the job started at `t0`.
struct JobPlace {
  int index = 0, count = 1;
  std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
};

// The frame's bar, its ETA and, in a sequence, the whole job's ETA (frames left at the pace so
// far).
void print_progress(const Progress& p, const std::string& prefix, const JobPlace& job) {
  const int width = 30;
  const int filled = int(p.fraction * width);
  const double mrays = p.seconds > 0 ? p.rays / p.seconds * 1e-6 : 0;
  const double eta = p.fraction > 0 ? p.seconds * (1 - p.fraction) / p.fraction : 0;
  std::string whole;
  if (job.count > 1) {
    const double done = job.index + p.fraction,
                 spent = std::chrono::duration<double>(std::chrono::steady_clock::now() - job.t0)
                             .count();
    whole = done > 0 ? fmt::format(", job {:.0f}s", spent * (job.count - done) / done) : "";
  }
  fmt::print(stderr, "\r{}[{}{}] {:5.1f}%  {:7.2f} Mrays/s  ETA {:.0f}s{}   ", prefix,
             std::string(size_t(filled), '#'), std::string(size_t(width - filled), ' '),
             100 * p.fraction, mrays, eta, whole);
}

bool on_path(const std::string& exe) {
  const char* path = std::getenv("PATH");
  if (!path) return false;
  std::string p = path;
  for (size_t s = 0, e; s <= p.size(); s = e + 1) {
    e = p.find(':', s);
    if (e == std::string::npos) e = p.size();
    const fs::path cand = fs::path(p.substr(s, e - s)) / exe;
    if (!p.substr(s, e - s).empty() && access(cand.c_str(), X_OK) == 0) return true;
  }
  return false;
}

// "A:B" or "A" (integers, possibly negative).
bool parse_frames(const std::string& text, int* first, int* last) {
  auto number = [](const std::string& t, int* v) {
    if (t.empty()) return false;
    char* end = nullptr;
    const long x = std::strtol(t.c_str(), &end, 10);
    if (*end || x < -1000000000 || x > 1000000000) return false;
    *v = int(x);
    return true;
  };
  const size_t colon = text.find(':');
  if (colon == std::string::npos) return number(text, first) && number(text, last);
  return number(text.substr(0, colon), first) && number(text.substr(colon + 1), last);
}

// The beauty image with the coin markers drawn over it in red, for looking at.
OutputImage with_overlay(const OutputImage& img, const ImageLayer& coins) {
  OutputImage o;
  o.width = img.width;
  o.height = img.height;
  o.metadata = img.metadata;
  ImageLayer b = img.layers[0];
  for (size_t i = 0; i < coins.data.size(); ++i) {
    const float c = coins.data[i];
    const float rgb[3] = {1.0f, 0.1f, 0.05f};
    for (int k = 0; k < 3; ++k)
      b.data[i * 4 + size_t(k)] = b.data[i * 4 + size_t(k)] * (1 - c) + rgb[k] * c;
    b.data[i * 4 + 3] = std::max(b.data[i * 4 + 3], c);
  }
  o.layers.push_back(std::move(b));
  return o;
}

// The coin overlay needs the whole beauty image: that render keeps its frame in a film.
int render_with_overlay(const RenderArgs& a, const Scene& scene, const Renderer& renderer,
                        const std::vector<Aov>& aovs, double frame, const fs::path& out,
                        const RenderOptions& opt, RenderStats* st) {
  Film film(scene.render.width, scene.render.height, aovs, scene.render.tile_size);
  {
    const RenderPhase phase;
    *st = renderer.render(film, opt);
  }
  if (st->cancelled) {
    fmt::print(stderr, "interrupted: {} not written\n", out.string());
    return kInterrupted;
  }
  OutputImage img = film.output();
  img.metadata = frame_metadata(scene, frame);
  img.layers.push_back(coins_layer(scene));
  fs::path marked = out;
  marked.replace_extension(".coins.png");
  write_png(marked, with_overlay(img, img.layers.back()));
  if (!a.quiet) fmt::print(messages(), "coin overlay written to {}\n", marked.string());
  if (render_format(out) == ".png") {
    write_png(out, img);
    fs::path exr = out;
    exr.replace_extension(".exr");
    write_exr(exr, img);
    if (!a.quiet) fmt::print(messages(), "AOVs written to {}\n", exr.string());
  } else {
    write_exr(out, img);
  }
  return kOk;
}

// Renders one frame to `out`; returns an exit code.
int render_frame(const RenderArgs& a, const Scene& scene, const Renderer& renderer,
                 const std::vector<Aov>& aovs, double frame, const fs::path& out,
                 const std::string& prefix, const fs::path& checkpoint, double checkpoint_every,
                 const fs::path& stats, TileFarm* farm, const JobPlace& place = {}) {
  const bool bar = !a.quiet && isatty(STDERR_FILENO);
  // An MPI job's output goes to a log (mpirun forwards it through pipes): a line every 10 s.
  const bool lines = !a.quiet && !bar && farm;
  auto last = std::chrono::steady_clock::now();
  std::function<void(const Progress&)> on_progress;
  if (bar || lines)
    on_progress = [&, bar](const Progress& p) {
      const auto now = std::chrono::steady_clock::now();
      if (now - last < std::chrono::milliseconds(bar ? 100 : 10000) && (!bar || p.fraction < 1))
        return;
      last = now;
      print_progress(p, prefix, place);
      if (!bar) fmt::print(stderr, "\n");
    };
  RenderStats st;
  std::vector<TileTiming> tile_times;
  if (a.coins_overlay) {
    RenderOptions opt;
    opt.threads = a.threads.value_or(0);
    opt.aovs = aovs;
    opt.cancel = &interrupt_flag();
    opt.on_progress = on_progress;
    opt.farm = farm;
    if (!stats.empty()) opt.tile_times = &tile_times;
    const int rc = render_with_overlay(a, scene, renderer, aovs, frame, out, opt, &st);
    if (bar) fmt::print(stderr, "\r{}\r", std::string(100, ' '));
    if (rc != kOk) return rc;
  } else {
    FrameJob job{scene,
                 renderer,
                 aovs,
                 {},
                 {},
                 frame_metadata(scene, frame),
                 checkpoint,
                 checkpoint_every,
                 a.threads.value_or(0),
                 on_progress,
                 stats.empty() ? nullptr : &tile_times,
                 farm};
    if (render_format(out) == ".png") {
      job.png = out;
      // AOVs go beside a PNG, with the beauty, into an EXR of the same name.
      if (!aovs.empty()) job.exr = fs::path(out).replace_extension(".exr");
    } else {
      job.exr = out;
    }
    FrameResult r;
    {
      const RenderPhase phase;
      r = render_to_files(job);
    }
    if (bar) fmt::print(stderr, "\r{}\r", std::string(100, ' '));
    st = r.stats;
    if (r.resumed && !a.quiet)
      fmt::print(messages(), "resumed from {}: {} tiles were done\n", checkpoint.string(),
                 r.resumed_tiles);
    if (r.interrupted) {
      const fs::path partial =
          FrameOutput::with_suffix(job.png.empty() ? job.exr : job.png, ".partial");
      fmt::print(
          stderr, "interrupted: {} not written; the image so far is in {}{}\n", out.string(),
          partial.string(),
          checkpoint.empty() ? ""
          : farm             ? fmt::format("; the finished tiles are in {}: run the same mpirun "
                                                       "command again to resume",
                                           checkpoint.string())
                 : fmt::format("; resume with: anamorph render --resume {}", checkpoint.string()));
      return kInterrupted;
    }
    if (!job.exr.empty() && !job.png.empty() && !a.quiet)
      fmt::print(messages(), "AOVs written to {}\n", job.exr.string());
    if (r.time_limited && !a.quiet)
      fmt::print(messages(), "{}: time limit of {} s reached after {}; {}\n", out.string(),
                 scene.render.time_limit, r.reached,
                 checkpoint.empty() ? "render with --checkpoint FILE to be able to continue"
                                    : fmt::format("continue with: anamorph render --resume {}",
                                                  checkpoint.string()));
  }
  if (!stats.empty()) {
    set_interrupt_note(fmt::format("{} not written ({} was)", stats.string(), out.string()));
    write_tile_stats(stats, scene, frame, a.threads.value_or(0), st, std::move(tile_times));
    if (!a.quiet) fmt::print(messages(), "tile costs written to {}\n", stats.string());
  }
  if (!a.quiet) {
    const double per_pixel =
        double(st.samples) / (double(scene.render.width) * scene.render.height);
    // (The scheme by its render.antialias name: lattice or pixel.)
    const std::string sampling = scene.render.adaptive()
                                     ? fmt::format("adaptive ({}), {:.2f} samples/pixel",
                                                   name_of(scene.render.antialias), per_pixel)
                                     : fmt::format("{} spp", scene.render.spp);
    fmt::print(messages(),
               "{}: {}x{}, {}, {} in {:.2f} s, {:.2f} Mrays/s ({:.3f} M rays), {} NaN/Inf samples "
               "dropped\n",
               out.string(), scene.render.width, scene.render.height, sampling,
               name_of(scene.render.integrator), st.seconds, st.mrays_per_second(), st.rays * 1e-6,
               st.nan_samples);
  }
  if (st.nan_samples > 0)
    fmt::print(stderr,
               "warning: {} samples had NaN or Inf radiance and were dropped (first at pixel {},{} "
               "sample {})\n",
               st.nan_samples, st.nan_x, st.nan_y, st.nan_sample);
  return kOk;
}

// Whether the machine can hold the render; if not, says why (the caller exits 2 before any
// allocation or output file).
bool fits_in_memory(const RenderArgs& a, const Scene& scene, const std::vector<Aov>& aovs,
                    const std::string& out) {
  const RenderSettings& rs = scene.render;
  RenderShape shape;
  shape.width = rs.width;
  shape.height = rs.height;
  shape.tile_size = rs.tile_size;
  shape.threads = a.threads.value_or(0) > 0 ? *a.threads : int(std::thread::hardware_concurrency());
  shape.aov_floats = aov_floats(aovs);
  shape.whole_film = a.coins_overlay || renders_in_passes(rs);
  shape.active_mask = !Renderer::streams(rs);
  shape.png = render_format(out) == ".png";
  shape.exr = !shape.png || !aovs.empty();
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

// A frame already rendered: its file is there (files appear only when complete) and readable, and
// no checkpoint of it is left (a time limit's image keeps one, to continue from).
bool frame_exists(const fs::path& out, const fs::path& checkpoint) {
  if (!fs::is_regular_file(out) || (!checkpoint.empty() && fs::exists(checkpoint))) return false;
  try {
    return read_metadata(out).count("anamorph.command") > 0;
  } catch (const std::exception&) {
    return false;
  }
}

// `render --resume FILE`: the command that started the checkpoint, run again (a frame sequence
// skips the frames it finished).
int resume(const std::string& file, const ResumeOptions& with) {
  const CheckpointReader reader(file);
  std::vector<std::string> args;
  for (const auto& [k, v] : reader.identity())
    if (k == "command")
      for (size_t s = 0, e; s < v.size(); s = e + 1)
        args.push_back(v.substr(s, (e = v.find('\0', s)) - s));
  if (args.empty() || args[0] != "render" ||
      std::find(args.begin(), args.end(), "--resume") != args.end())
    throw CheckpointError(fmt::format("checkpoint '{}' does not say how it was started", file));
  apply_honoured(with, args);
  set_command_args(args);
  const bool frames = std::find(args.begin(), args.end(), "--frames") != args.end();
  if (frames && std::find(args.begin(), args.end(), "--skip-existing") == args.end())
    args.push_back("--skip-existing");
  CLI::App app;
  std::function<int()> runner;
  add_render(app, runner);
  std::reverse(args.begin(), args.end());  // CLI11 takes a vector last argument first
  app.parse(args);
  return runner ? runner() : kBadInput;
}

// The head rank of an MPI job renders nothing itself: it builds no acceleration structure.
std::unique_ptr<Renderer> make_renderer(const Scene& scene, const TileFarm* farm) {
  return farm ? std::make_unique<Renderer>(scene, Renderer::FarmOnly{})
              : std::make_unique<Renderer>(scene);
}

// The scene of a sequence's current frame and its renderer. When the keys change only camera,
// image or render settings, the frames share the first one's geometry, lights and acceleration
// structure: only the view is read again. The head and the workers of an MPI job load frames
// through this alike.
struct FrameScene {
  std::unique_ptr<Scene> scene;
  std::unique_ptr<Renderer> renderer;
  // Loads `frame`; true when it needs a new renderer (the old one is gone then).
  bool load_frame(const SceneOptions& o, const std::vector<std::string>& extra, double frame) {
    if (scene && animates_view_only(*scene)) {
      load_view_into(o, extra, frame, *scene);
      return false;
    }
    renderer.reset();  // (it refers to the scene)
    scene = std::make_unique<Scene>(load(o, extra, frame));
    return true;
  }
};

// A worker rank of an MPI job: loads the frames the head names (as the head does, so the scene
// is the same) and renders the tiles it is handed.
int serve(const RenderArgs& a, const std::vector<std::string>& extra,
          const std::vector<Aov>& aovs) {
  FrameScene current;
  return dist::serve_tiles(a.threads.value_or(0), aovs, [&](double frame) {
    if (current.load_frame(a.scene, extra, frame))
      current.renderer = std::make_unique<Renderer>(*current.scene);
    const RenderSettings& rs = current.scene->render;
    return dist::WorkerFrame{current.renderer.get(), rs.width, rs.height};
  });
}

int run(const RenderArgs& a) {
  if (!a.resume.empty()) {
    if (!a.scene.scene.empty()) {
      fmt::print(stderr, "error: --resume takes everything from the checkpoint: give no scene\n");
      return kBadInput;
    }
    if (!a.with_resume.refused.empty()) {
      print_error(refused_message(a.with_resume));
      return kBadInput;
    }
    return resume(a.resume, a.with_resume);
  }
  std::vector<std::string> extra;
  if (a.spp) extra.push_back(fmt::format("render.spp={}", *a.spp));
  if (a.seed) extra.push_back(fmt::format("render.seed={}", *a.seed));
  if (a.integrator) extra.push_back(fmt::format("render.integrator=\"{}\"", *a.integrator));
  if (a.sampler) extra.push_back(fmt::format("render.sampler=\"{}\"", *a.sampler));
  std::vector<Aov> aovs;
  RenderArgs args = a;
  try {
    // "coins" is drawn from the camera after rendering, not sampled: take it out of the list.
    std::string list;
    for (size_t s = 0; s <= a.aovs.size() && !a.aovs.empty();) {
      size_t e = a.aovs.find(',', s);
      if (e == std::string::npos) e = a.aovs.size();
      const std::string name = a.aovs.substr(s, e - s);
      if (name == "coins")
        args.coins_overlay = true;
      else
        list += (list.empty() ? "" : ",") + name;
      s = e + 1;
    }
    aovs = parse_aovs(list);
  } catch (const std::invalid_argument& e) {
    print_error(fmt::format("--aov: {}", e.what()));
    return kBadInput;
  }
  const std::string out =
      a.output.empty() ? default_render_output(a.scene.scene, !a.frames.empty()) : a.output;
  // What the outputs are checked against (app/output_guard.h): before loading the scene file,
  // after it every file the load read.
  RenderOutputs outs{out,          a.output.empty(), !aovs.empty(), args.coins_overlay,
                     a.checkpoint, a.stats,          a.video,       ""};
  const std::vector<FileRead> scene_file = scene_file_input(a.scene.scene);
  double every = 60;
  if (!parse_duration(a.checkpoint_every, &every)) {
    print_error(fmt::format("--checkpoint-every {}: expected seconds, e.g. 60, 60s, 5m or 1h",
                            a.checkpoint_every));
    return kBadInput;
  }
  if (a.scene.scene.empty()) {
    fmt::print(stderr, "error: render needs a scene file (or --resume CHECKPOINT)\n");
    return kBadInput;
  }
  if (render_format(out).empty()) {
    print_error(fmt::format("-o {}: unsupported image format (use .png or .exr)", out));
    return kBadInput;
  }
  if (is_standard_output(out)) messages_to_stderr();  // (`-o /dev/stdout`: the image alone)
  // Under MPI the head (rank 0) goes on below, handing tiles to the workers through `farm`.
  std::unique_ptr<dist::HeadFarm> farm;
  if (dist::World::size() > 1) {
    if (dist::World::rank() > 0) return serve(args, extra, aovs);
    farm = std::make_unique<dist::HeadFarm>(aovs, &interrupt_flag());
  }
  if (a.frames.empty()) {
    if (!a.video.empty()) {
      fmt::print(stderr, "error: --video needs --frames A:B\n");
      return kBadInput;
    }
    if (a.skip_existing && frame_exists(out, a.checkpoint)) {
      if (!a.quiet) fmt::print(messages(), "{} exists: skipped\n", out);
      return kOk;
    }
    check_render_outputs(outs, scene_file);
    set_interrupt_note(out + " not written");
    const Scene scene = load(args.scene, extra, 0);
    check_render_outputs(outs, scene.inputs);
    if (!fits_in_memory(args, scene, aovs, out)) return kBadInput;
    const std::unique_ptr<Renderer> renderer = make_renderer(scene, farm.get());
    if (farm) farm->begin_frame(0);
    const int rc = render_frame(args, scene, *renderer, aovs, 0, out, "", a.checkpoint, every,
                                a.stats, farm.get());
    if (farm && rc == kInterrupted) dist::World::abort_on_exit(rc);  // a worker may be gone
    return rc;
  }

  // A sequence: frames A..B inclusive, written through a printf pattern.
  int first = 0, last = 0;
  if (!parse_frames(a.frames, &first, &last)) {
    print_error(
        fmt::format("--frames {}: expected FIRST:LAST (e.g. 0:59) or one frame number", a.frames));
    return kBadInput;
  }
  if (last < first) {
    print_error(fmt::format("--frames {}: the last frame comes before the first", a.frames));
    return kBadInput;
  }
  if (const auto why = frame_pattern_error(out)) {
    print_error(
        fmt::format("-o {}: with --frames the output needs one frame-number pattern and no "
                    "other % (write %% for a percent sign), e.g. out/frame_%04d.png ({})",
                    out, *why));
    return kBadInput;
  }
  // With --frames each frame has its own checkpoint and stats file: their names need a pattern.
  for (const auto& [option, name, example] :
       {std::tuple{"--checkpoint", a.checkpoint, "render_%04d.ckpt"},
        std::tuple{"--stats", a.stats, "stats_%04d.json"}})
    if (const auto why = name.empty() ? std::nullopt : frame_pattern_error(name)) {
      print_error(
          fmt::format("{} {}: with --frames each frame has its own file, so the name needs a "
                      "frame-number pattern, e.g. {} ({})",
                      option, name, example, *why));
      return kBadInput;
    }
  FrameScene current;
  JobPlace place;
  place.count = last - first + 1;
  const auto frame_outputs = [&](int f) {
    RenderOutputs o = outs;
    o.out = fmt::sprintf(out, f);
    o.checkpoint = a.checkpoint.empty() ? std::string() : fmt::sprintf(a.checkpoint, f);
    o.stats = a.stats.empty() ? std::string() : fmt::sprintf(a.stats, f);
    o.frame = fmt::format(" (frame {})", f);
    return o;
  };
  check_render_outputs(frame_outputs(first), scene_file);
  if (!a.video.empty() && !on_path("ffmpeg")) {
    fmt::print(stderr,
               "error: --video needs ffmpeg, which is not on the PATH (install it, e.g. `apt-get "
               "install ffmpeg`, "
               "or drop --video; the frames alone need nothing else)\n");
    return kBadInput;
  }
  for (int f = first; f <= last; ++f, ++place.index) {
    if (a.skip_existing &&
        frame_exists(fmt::sprintf(out, f),
                     a.checkpoint.empty() ? std::string() : fmt::sprintf(a.checkpoint, f))) {
      if (!a.quiet) fmt::print(messages(), "{} exists: skipped\n", fmt::sprintf(out, f));
      --place.count, --place.index;  // (the job's ETA counts the frames it renders)
      continue;
    }
    const std::string file = fmt::sprintf(out, f);
    set_interrupt_note(
        fmt::format("{} not written{}", file,
                    f > first ? fmt::format("; frames {}..{} were written", first, f - 1) : ""));
    const bool fresh = current.load_frame(args.scene, extra, f);
    check_render_outputs(frame_outputs(f), current.scene->inputs);
    if (place.index == 0) check_frames(args.scene, extra, f, last, *current.scene);
    if (!fits_in_memory(args, *current.scene, aovs, file)) return kBadInput;
    if (fresh) current.renderer = make_renderer(*current.scene, farm.get());
    if (farm) farm->begin_frame(f);
    const int rc =
        render_frame(args, *current.scene, *current.renderer, aovs, f, file,
                     fmt::format("frame {} ({} of {}) ", f, f - first + 1, last - first + 1),
                     a.checkpoint.empty() ? std::string() : fmt::sprintf(a.checkpoint, f), every,
                     a.stats.empty() ? std::string() : fmt::sprintf(a.stats, f), farm.get(), place);
    if (farm && rc == kInterrupted) dist::World::abort_on_exit(rc);  // a worker may be gone
    if (rc != kOk) {
      if (f > first)
        fmt::print(stderr, "frames {}..{} were written; frame {} and later were not\n", first,
                   f - 1, f);
      return rc;
    }
  }
  if (!a.video.empty())
    return assemble_video(out, first, last - first + 1, a.fps, a.video, a.quiet);
  return kOk;
}

}  // namespace

void add_render(CLI::App& app, std::function<int()>& runner) {
  auto a = std::make_shared<RenderArgs>();
  CLI::App* cmd = app.add_subcommand("render", "Render a scene to an image (PNG or EXR)");
  a->scene.add_to(*cmd, false);
  cmd->add_option(
      "-o,--output", a->output,
      "Output image (.png or .exr); default out/<scene name>.png (out/<scene name>_%04d.png "
      "with --frames). With --frames, a pattern such as out/frame_%04d.png");
  cmd->add_option("--spp", a->spp,
                  "Samples per pixel (overrides render.spp; implies uniform sampling)")
      ->check(CLI::Range(1, 1 << 20));
  cmd->add_option("--threads", a->threads, "Worker threads (default: all cores)")
      ->check(thread_count_check());
  cmd->add_option("--seed", a->seed, "Random seed (overrides render.seed)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--integrator", a->integrator,
                  "whitted | path | albedo | normal | depth | position | id | uv");
  cmd->add_option("--sampler", a->sampler, "center | stratified | random");
  cmd->add_option("--aov", a->aovs,
                  "Extra layers written to EXR (beside a PNG: <output>.exr): "
                  "albedo,normal,depth,position,id,uv,spp,coins "
                  "(coins also writes <output>.coins.png with the markers drawn in)");
  cmd->add_option("--frames", a->frames,
                  "Render frames FIRST:LAST of the scene's [[animate]] keys (inclusive)");
  cmd->add_option("--video", a->video,
                  "After --frames, assemble the frames into this video with ffmpeg");
  cmd->add_option("--fps", a->fps, "Frames per second of --video (default 30)")
      ->check(CLI::Range(1, 1000));
  cmd->add_flag("-q,--quiet", a->quiet, "No progress bar or summary");
  cmd->add_option("--checkpoint", a->checkpoint,
                  "Keep a checkpoint here while rendering (with --frames, a pattern such as "
                  "ckpt/frame_%04d.ckpt); an existing one of the same render is resumed");
  cmd->add_option("--stats", a->stats,
                  "Write every tile's cost (time, samples, rays) as JSON, for planning cluster "
                  "renders (a frame pattern with --frames, e.g. stats_%04d.json)");
  cmd->add_option("--checkpoint-every", a->checkpoint_every,
                  "How often the checkpoint is forced to disk: 60s (default), 5m, 1h");
  cmd->add_option("--resume", a->resume,
                  std::string("Continue the render a checkpoint belongs to (the same command, "
                              "resumed); only ") +
                      kWithResume + " may be given with it");
  cmd->add_flag("--skip-existing", a->skip_existing,
                "Skip frames whose output file is already there (complete: files appear only "
                "when done)");
  cmd->callback([a, cmd, &runner] {
    if (!a->resume.empty()) a->with_resume = resume_options(*cmd);
    runner = [a] { return run(*a); };
  });
}

}  // namespace anamorph::app
