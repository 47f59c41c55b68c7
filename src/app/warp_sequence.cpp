// `anamorph warp --frames A:B`: frame f reads fmt::sprintf(INPUT, f) and writes
// fmt::sprintf(-o, f) through the camera of the scene at frame f ([[animate]] keys; only the
// view is read again when only the view is animated). Checked before anything is written: the
// patterns, every input frame present (a sequence with gaps is exit 2 naming the missing files),
// no output onto any input.
#include <fmt/format.h>
#include <fmt/printf.h>

#include <filesystem>

#include "app/frame_pattern.h"
#include "app/output_guard.h"
#include "app/warp_command.h"
#include "scene/scene_loader.h"

namespace anamorph::app {

namespace fs = std::filesystem;

namespace {

// --frames and both patterns: "" when fine, else the message.
std::string sequence_error(const WarpArgs& a, int* first, int* last) {
  if (!parse_frame_range(a.frames, first, last))
    return fmt::format("--frames {}: expected FIRST:LAST (e.g. 0:59) or one frame number",
                       a.frames);
  if (*last < *first)
    return fmt::format("--frames {}: the last frame comes before the first", a.frames);
  for (const auto& [what, pattern] : {std::pair{"INPUT", a.input}, std::pair{"-o", a.output}})
    if (const auto why = frame_pattern_error(pattern))
      return fmt::format(
          "{} {}: with --frames it needs one frame-number pattern and no other % (write %% "
          "for a percent sign), e.g. frame_%04d.png ({})",
          what, pattern, *why);
  return "";
}

// The input frames that are not there: "" when none is missing.
std::string missing_frames(const std::string& pattern, int first, int last) {
  std::vector<int> missing;
  for (int f = first; f <= last; ++f)
    if (!fs::is_regular_file(fmt::sprintf(pattern, f))) missing.push_back(f);
  if (missing.empty()) return "";
  std::string list;
  for (size_t i = 0; i < missing.size() && i < 5; ++i)
    list += fmt::format("{}{} ({})", i ? ", " : "", missing[i], fmt::sprintf(pattern, missing[i]));
  if (missing.size() > 5) list += fmt::format(" and {} more", missing.size() - 5);
  return fmt::format("{}: the sequence {}:{} has gaps: {} frame{} missing: {}", pattern, first,
                     last, missing.size(), missing.size() > 1 ? "s are" : " is", list);
}

}  // namespace

int warp_sequence(const WarpArgs& a) {
  int first = 0, last = 0;
  std::string why = sequence_error(a, &first, &last);
  if (why.empty()) why = missing_frames(a.input, first, last);
  if (!why.empty()) {
    print_error(why);
    return kBadInput;
  }
  std::vector<FileRead> inputs = scene_file_input(a.scene.scene);
  std::vector<std::pair<fs::path, std::string>> outputs;
  for (int f = first; f <= last; ++f) {
    inputs.push_back({fmt::sprintf(a.input, f), fmt::format("the input image of frame {}", f)});
    const std::string out = fmt::sprintf(a.output, f);
    outputs.emplace_back(out, fmt::format("-o {} (frame {})", out, f));
  }
  check_outputs(inputs, outputs);
  std::optional<Scene> s;
  bool view_only = false;  // (then a frame reads only [camera], [image], [render] again)
  // What an interruption says while frame f is warped (and, once it is written, of the next).
  const auto note = [&](int f) {
    return f > last
               ? fmt::format("frames {}..{} were written", first, last)
               : fmt::format(
                     "{} not written{}", fmt::sprintf(a.output, f),
                     f > first ? fmt::format("; frames {}..{} were written", first, f - 1) : "");
  };
  for (int f = first; f <= last; ++f) {
    const std::string in = fmt::sprintf(a.input, f), out = fmt::sprintf(a.output, f);
    set_interrupt_note(note(f));
    try {
      if (!s) {  // (the whole scene; its inputs checked against every output)
        s.emplace(load(a.scene, {}, f));
        view_only = animates_view_only(*s);
        check_outputs(s->inputs, outputs);
      } else if (view_only) {
        load_view_into(a.scene, {}, f, *s);
      } else {
        s.emplace(load(a.scene, {}, f));
        check_outputs(s->inputs, outputs);
      }
      warp_frame(a, *s, in, out,
                 fmt::format("frame {} ({} of {}) ", f, f - first + 1, last - first + 1),
                 [&] { set_interrupt_note(note(f + 1)); });
    } catch (...) {
      if (f > first)
        fmt::print(stderr, "frames {}..{} were written; frame {} and later were not\n", first,
                   f - 1, f);
      throw;
    }
  }
  return kOk;
}

}  // namespace anamorph::app
