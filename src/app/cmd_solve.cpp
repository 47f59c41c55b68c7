// `anamorph solve SCENE [-o SOLVED.toml]`: the camera's [[camera.free]] keys solved for its
// [[camera.constraint]] entries (solve/camera_solve.h, docs/solve.md). Prints every free key's
// start and solved value and every constraint's residual and whether it is met; with -o writes
// the scene's own text with the solved values spliced in (the editor's save: comments and layout
// kept). Constraints not met: a report of which conflict, exit 2, nothing written.
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <cmath>
#include <filesystem>

#include "app/common.h"
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

// The scene's text with the solved values spliced in.
std::string solved_text(const std::string& text, const fs::path& file,
                        const solve::SolveReport& r) {
  toml::table t = parse_toml(text, file.string());
  for (const auto& [key, value] : r.texts) {
    const toml::table v = parse_value_text(value, key);
    set_path(t, key, *v.get("v"), {file.string(), 0, 0});
  }
  const server::SavedText saved = server::saved_text(text, t);
  if (!saved.reads_back)
    throw std::runtime_error("the solved scene cannot be written as TOML that reads back");
  return saved.text;
}

int run_solve(const SolveArgs& a) {
  const fs::path out = a.output;
  std::vector<std::pair<fs::path, std::string>> outputs;
  if (!a.output.empty()) outputs.emplace_back(out, "-o " + a.output);
  check_outputs(scene_file_input(a.scene.scene), outputs);
  set_interrupt_note(a.output.empty() ? "" : a.output + " not written");
  const Scene s = load(a.scene);
  check_outputs(s.inputs, outputs);
  solve::SolveInput in;
  in.text = read_text_file(a.scene.scene);
  in.file = a.scene.scene;
  in.overrides = a.scene.overrides();
  in.loaded = &s;
  const solve::SolveReport r = solve::solve_camera(in);
  print_report(r);
  if (!r.all_met()) {
    print_error("constraints not met (nothing written):");
    for (const std::string& line : unmet_lines(r)) fmt::print(stderr, "  {}\n", printable(line));
    return kBadInput;
  }
  if (!a.output.empty()) {
    const std::string text = solved_text(in.text, in.file, r);
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
  cmd->callback([a, &runner] { runner = [a] { return run_solve(*a); }; });
}

}  // namespace anamorph::app
