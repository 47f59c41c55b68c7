// What `render --resume CHECKPOINT` does with the other options on its command line. A resume
// continues the render exactly as the checkpoint's command started it, so an option that would
// change the image, where it goes or what else is written (-o, --width, --spp, --set, --aov,
// --frames, --stats, ...) is refused (exit 2), never silently ignored; the few that leave every
// output file the same (--threads: images are bit-identical on any thread count; --quiet;
// --checkpoint-every; --skip-existing, which a resumed sequence uses anyway) are honoured.
#pragma once

#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace anamorph::app {

struct ResumeOptions {
  std::vector<std::string> refused;  // as typed: "-o", "--spp", ...
  // To put in place of the checkpoint's own: "--threads" and its value, "--quiet" and none.
  std::vector<std::pair<std::string, std::optional<std::string>>> honoured;
};

// The options given to `cmd` (the parsed render subcommand) beside --resume.
ResumeOptions resume_options(const CLI::App& cmd);

// "--resume continues the render as it was started: -o, --spp would change it ...".
std::string refused_message(const ResumeOptions& r);

// `args` (the command that started the checkpoint) with the honoured options in place of the
// same options there.
void apply_honoured(const ResumeOptions& r, std::vector<std::string>& args);

// For --help and the README: the options that may be given with --resume.
inline constexpr const char* kWithResume =
    "--threads, --quiet, --checkpoint-every, --skip-existing";

}  // namespace anamorph::app
