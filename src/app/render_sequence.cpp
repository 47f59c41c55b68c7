// What `anamorph render` renders: one frame, or with --frames A:B a sequence written through the
// output's printf pattern (app/frame_pattern.h), each frame checked, skipped when it exists
// (--skip-existing), and with --video assembled by ffmpeg (app/video.h).
#include <fmt/format.h>
#include <fmt/printf.h>

#include <tuple>

#include "app/frame_check.h"
#include "app/frame_pattern.h"
#include "app/interrupt.h"
#include "app/output_guard.h"
#include "app/render_command.h"
#include "app/video.h"
#include "dist/head.h"
#include "dist/world.h"
#include "io/image_io.h"

namespace anamorph::app {

namespace fs = std::filesystem;

namespace {

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

// The frame's files: the patterns filled in with `f`.
FrameFiles frame_files(const RenderSetup& s, int f) {
  const RenderArgs& a = s.args;
  return {fmt::sprintf(s.out, f),
          a.checkpoint.empty() ? std::string() : fmt::sprintf(a.checkpoint, f),
          a.stats.empty() ? std::string() : fmt::sprintf(a.stats, f)};
}

// What the outputs of frame `f` are checked against.
RenderOutputs frame_outputs(const RenderSetup& s, int f) {
  const FrameFiles files = frame_files(s, f);
  RenderOutputs o = s.outs;
  o.out = files.out;
  o.checkpoint = files.checkpoint;
  o.stats = files.stats;
  o.frame = fmt::format(" (frame {})", f);
  return o;
}

// --frames and the patterns it needs; kOk or kBadInput (the error printed).
int check_sequence(const RenderSetup& s, int* first, int* last) {
  const RenderArgs& a = s.args;
  if (!parse_frame_range(a.frames, first, last)) {
    print_error(
        fmt::format("--frames {}: expected FIRST:LAST (e.g. 0:59) or one frame number", a.frames));
    return kBadInput;
  }
  if (*last < *first) {
    print_error(fmt::format("--frames {}: the last frame comes before the first", a.frames));
    return kBadInput;
  }
  if (const auto why = frame_pattern_error(s.out)) {
    print_error(
        fmt::format("-o {}: with --frames the output needs one frame-number pattern and no "
                    "other % (write %% for a percent sign), e.g. out/frame_%04d.png ({})",
                    s.out, *why));
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
  return kOk;
}

// Frame `f` of first..last loaded (or only its view) and rendered; returns an exit code.
int sequence_frame(const RenderSetup& s, FrameScene& current, int f, int first, int last,
                   const JobPlace& place) {
  const FrameFiles files = frame_files(s, f);
  set_interrupt_note(
      fmt::format("{} not written{}", files.out,
                  f > first ? fmt::format("; frames {}..{} were written", first, f - 1) : ""));
  const bool fresh = current.load_frame(s.args.scene, s.extra, f, s.aovs);
  check_render_outputs(frame_outputs(s, f), current.scene->inputs);
  if (place.index == 0) check_frames(s.args.scene, s.extra, f, last, *current.scene);
  if (!denoise_applies(s, *current.scene, files.out)) return kBadInput;
  if (!fits_in_memory(s, *current.scene, files.out)) return kBadInput;
  if (fresh) current.renderer = make_renderer(*current.scene, s.farm);
  if (s.farm) s.farm->begin_frame(f);
  const int rc =
      render_frame(s, *current.scene, *current.renderer, f, files,
                   fmt::format("frame {} ({} of {}) ", f, f - first + 1, last - first + 1), place);
  if (s.farm && rc == kInterrupted) dist::World::abort_on_exit(rc);  // a worker may be gone
  if (rc != kOk && f > first)
    fmt::print(stderr, "frames {}..{} were written; frame {} and later were not\n", first, f - 1,
               f);
  return rc;
}

}  // namespace

int render_single(const RenderSetup& s) {
  const RenderArgs& a = s.args;
  if (!a.video.empty()) {
    fmt::print(stderr, "error: --video needs --frames A:B\n");
    return kBadInput;
  }
  if (a.skip_existing && frame_exists(s.out, a.checkpoint)) {
    if (!a.quiet) fmt::print(messages(), "{} exists: skipped\n", s.out);
    return kOk;
  }
  check_render_outputs(s.outs, s.scene_file);
  set_interrupt_note(s.out + " not written");
  Scene scene = load(a.scene, s.extra, 0);
  attach_next_frame(a.scene, s.extra, s.aovs, scene);
  check_render_outputs(s.outs, scene.inputs);
  if (!denoise_applies(s, scene, s.out)) return kBadInput;
  if (!fits_in_memory(s, scene, s.out)) return kBadInput;
  const std::unique_ptr<Renderer> renderer = make_renderer(scene, s.farm);
  if (s.farm) s.farm->begin_frame(0);
  const int rc = render_frame(s, scene, *renderer, 0, {s.out, a.checkpoint, a.stats}, "");
  if (s.farm && rc == kInterrupted) dist::World::abort_on_exit(rc);  // a worker may be gone
  return rc;
}

int render_sequence(const RenderSetup& s) {
  const RenderArgs& a = s.args;
  int first = 0, last = 0;
  if (const int rc = check_sequence(s, &first, &last); rc != kOk) return rc;
  check_render_outputs(frame_outputs(s, first), s.scene_file);
  if (!a.video.empty() && !video_tool_found()) return kBadInput;
  FrameScene current;
  JobPlace place;
  place.count = last - first + 1;
  for (int f = first; f <= last; ++f, ++place.index) {
    const FrameFiles files = frame_files(s, f);
    if (a.skip_existing && frame_exists(files.out, files.checkpoint)) {
      if (!a.quiet) fmt::print(messages(), "{} exists: skipped\n", files.out);
      --place.count, --place.index;  // (the job's ETA counts the frames it renders)
      continue;
    }
    if (const int rc = sequence_frame(s, current, f, first, last, place); rc != kOk) return rc;
  }
  if (!a.video.empty())
    return assemble_video(s.out, first, last - first + 1, a.fps, a.video, a.quiet);
  return kOk;
}

}  // namespace anamorph::app
