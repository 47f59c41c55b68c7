// `anamorph render --resume CHECKPOINT`: the command that started the checkpoint (its identity's
// "command"), parsed and run again with the options honoured beside --resume (resume_options.h).
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <algorithm>

#include "app/render_command.h"
#include "render/checkpoint.h"

namespace anamorph::app {

namespace {

// The command that started the checkpoint `file`, as its arguments.
std::vector<std::string> checkpoint_command(const std::string& file) {
  const CheckpointReader reader(file);
  std::vector<std::string> args;
  for (const auto& [k, v] : reader.identity())
    if (k == "command")
      for (size_t s = 0, e; s < v.size(); s = e + 1)
        args.push_back(v.substr(s, (e = v.find('\0', s)) - s));
  if (args.empty() || args[0] != "render" ||
      std::find(args.begin(), args.end(), "--resume") != args.end())
    throw CheckpointError(fmt::format("checkpoint '{}' does not say how it was started", file));
  return args;
}

// The command run again (a frame sequence skips the frames it finished).
int resume(const std::string& file, const ResumeOptions& with) {
  std::vector<std::string> args = checkpoint_command(file);
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

}  // namespace

int resume_render(const RenderArgs& a) {
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

}  // namespace anamorph::app
