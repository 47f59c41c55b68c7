// `anamorph solve SCENE [--frames A:B] [-o SOLVED.toml]`: the camera's [[camera.free]] keys
// solved for its [[camera.constraint]] entries (solve/camera_solve.h, docs/solve.md). Prints every
// free key's start and solved value and every constraint's residual and whether it is met; with
// -o writes the scene's own text with the solved values spliced in (the editor's save: comments
// and layout kept). With --frames, each frame is loaded with its [[animate]] values and solved
// from the previous frame's solution, and -o adds one [[animate]] entry per free key. Constraints
// not met (at any frame): a report of which conflict, exit 2, nothing written.
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <cmath>
#include <filesystem>
#include <optional>

#include "app/common.h"
#include "app/frame_pattern.h"
#include "app/output_guard.h"
#include "io/image_io.h"
#include "math/user_text.h"
#include "params/toml_parse.h"
#include "scene/load_common.h"
#include "scene/toml_edit.h"
#include "server/document_save.h"
#include "solve/camera_solve.h"

namespace anamorph::app {

namespace {

namespace fs = std::filesystem;

struct SolveArgs {
  SceneOptions scene;
  std::string output;
  std::string frames;
};

void print_report(const solve::SolveReport& r) {
  FILE* out = messages();
  fmt::print(out, "solved in {} iterations ({})\n", r.iterations, r.termination);
  for (const solve::ValueReport& v : r.values)
    fmt::print(out, "  {:<28} {:>14.9g} -> {:<18.12g} [{:g}, {:g}]{}\n", v.name, v.start, v.value,
               v.lo, v.hi, v.at_bound ? "  at its bound" : "");
  for (const solve::ConstraintReport& c : r.constraints) {
    const std::string residual = std::isinf(c.residual)
                                     ? std::string("not seen")
                                     : fmt::format("{:.6g} {}", c.residual, c.unit);
    fmt::print(out, "  {:<24} {:<13} residual {:<16} (tolerance {:g} {}) {}\n", c.where, c.kind,
               residual, c.tolerance, c.unit, c.met ? "met" : "NOT MET");
  }
}

// Which constraints are not met and why, one line each.
std::vector<std::string> unmet_lines(const solve::SolveReport& r) {
  std::vector<std::string> lines;
  for (const solve::ConstraintReport& c : r.constraints) {
    if (c.met) continue;
    std::string line = c.where + " (" + c.kind + "): ";
    if (!c.met_alone) {
      line += "cannot be met even alone: the free keys, within their bounds, do not reach it";
    } else if (c.conflicts.empty()) {
      line += "met alone, but not together with all the others";
    } else {
      line += "conflicts with";
      for (size_t i = 0; i < c.conflicts.size(); ++i) line += (i ? ", " : " ") + c.conflicts[i];
    }
    lines.push_back(std::move(line));
  }
  return lines;
}

// One frame's solution: the values as TOML text by key.
using Texts = std::vector<std::pair<std::string, std::string>>;

// The scene's text with the solved values spliced in; with frames (first, then one per frame from
// `first`), `keyed`: each key's values also as an [[animate]] entry (the first frame's values are
// its value).
std::string solved_text(const std::string& text, const fs::path& file,
                        const std::vector<Texts>& frames, bool keyed, int first) {
  toml::table t = parse_toml(text, file.string());
  const SourceLoc at{file.string(), 0, 0};
  for (const auto& [key, value] : frames.front())
    set_path(t, key, *parse_value_text(value, key).get("v"), at);
  if (keyed) {
    if (!t.contains("animate")) t.insert("animate", toml::array{});
    toml::array* animate = t.get_as<toml::array>("animate");
    for (size_t k = 0; k < frames.front().size(); ++k) {
      const std::string& key = frames.front()[k].first;
      toml::array keys;
      for (size_t f = 0; f < frames.size(); ++f) {
        toml::array entry{first + int64_t(f)};
        entry.push_back(*parse_value_text(frames[f][k].second, key).get("v"));
        keys.push_back(std::move(entry));
      }
      animate->push_back(toml::table{{"key", key}, {"keys", std::move(keys)}});
    }
  }
  const server::SavedText saved = server::saved_text(text, t);
  if (!saved.reads_back)
    throw std::runtime_error("the solved scene cannot be written as TOML that reads back");
  return saved.text;
}

// Solves the frames `first`..`last` (one frame when not --frames), each from the previous
// solution; prints each report. The solutions, or none when a frame's constraints are not met.
std::optional<std::vector<Texts>> solve_frames(
    const SolveArgs& a, int first, int last,
    std::vector<std::pair<fs::path, std::string>>& outputs) {
  solve::SolveInput in;
  in.text = read_text_file(a.scene.scene);
  in.file = a.scene.scene;
  in.overrides = a.scene.overrides();
  std::vector<Texts> solved;
  for (int f = first; f <= last; ++f) {
    const Scene s = load(a.scene, {}, f);
    check_outputs(s.inputs, outputs);
    in.loaded = &s;
    in.frame = f;
    if (!a.frames.empty()) fmt::print(messages(), "frame {}:\n", f);
    const solve::SolveReport r = solve::solve_camera(in);
    print_report(r);
    if (!r.all_met()) {
      print_error(a.frames.empty()
                      ? std::string("constraints not met (nothing written):")
                      : fmt::format("frame {}: constraints not met (nothing written):", f));
      for (const std::string& line : unmet_lines(r)) fmt::print(stderr, "  {}\n", printable(line));
      return std::nullopt;
    }
    in.start.clear();
    for (const solve::ValueReport& v : r.values) in.start.push_back(v.value);
    solved.push_back(r.texts);
  }
  return solved;
}

int run_solve(const SolveArgs& a) {
  int first = 0, last = 0;
  if (!a.frames.empty() && (!parse_frame_range(a.frames, &first, &last) || first > last)) {
    print_error(fmt::format("--frames {}: expected FIRST:LAST (integers, FIRST <= LAST)",
                            printable(a.frames)));
    return kBadInput;
  }
  const fs::path out = a.output;
  std::vector<std::pair<fs::path, std::string>> outputs;
  if (!a.output.empty()) outputs.emplace_back(out, "-o " + a.output);
  check_outputs(scene_file_input(a.scene.scene), outputs);
  set_interrupt_note(a.output.empty() ? "" : a.output + " not written");
  const std::optional<std::vector<Texts>> solved = solve_frames(a, first, last, outputs);
  if (!solved) return kBadInput;
  if (!a.output.empty()) {
    const std::string text = solved_text(read_text_file(a.scene.scene), a.scene.scene, *solved,
                                         !a.frames.empty(), first);
    AtomicFile f(out);
    f.write(text.data(), text.size());
    f.commit();
    fmt::print(messages(), "wrote {}\n", a.output);
  }
  return kOk;
}

}  // namespace

void add_solve(CLI::App& app, std::function<int()>& runner) {
  auto a = std::make_shared<SolveArgs>();
  CLI::App* cmd = app.add_subcommand(
      "solve",
      "Solve the camera's [[camera.free]] keys for its [[camera.constraint]] entries and print "
      "each constraint's residual (docs/solve.md)");
  a->scene.add_to(*cmd);
  cmd->add_option("-o,--output", a->output,
                  "Write the scene with the solved values (its comments and layout kept); not "
                  "written when a constraint is not met");
  cmd->add_option("--frames", a->frames,
                  "Solve frames FIRST:LAST of the scene's [[animate]] keys (inclusive), each from "
                  "the previous frame's solution; -o then keys the solved values per frame");
  cmd->callback([a, &runner] { runner = [a] { return run_solve(*a); }; });
}

}  // namespace anamorph::app
