// Shared pieces of the command-line front end: scene options every command takes, and the
// mapping of errors to messages and exit codes (0 ok, 1 runtime failure, 2 bad usage or scene,
// 3 interrupted: app/interrupt.h).
#pragma once

namespace CLI {
class App;
}

#include <atomic>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "app/interrupt.h"
#include "scene/scene.h"

namespace anamorph::app {

// kInterrupted: SIGINT, SIGTERM, SIGHUP or SIGQUIT (app/interrupt.h); during a render the image
// so far was written beside the output ("<name>.partial.<ext>") and, with --checkpoint, the
// render can be resumed.
enum ExitCode { kOk = 0, kFailure = 1, kBadInput = 2, kInterrupted = 3 };

struct SceneOptions {
  std::string scene;
  std::optional<int> width, height;
  std::vector<std::string> set;
  std::optional<std::string> camera, env;  // --camera, --env (before --set, which wins)
  void add_to(CLI::App& cmd, bool required = true);
  std::vector<std::string> overrides() const;  // --set plus --width/--height as overrides
};

// Loads the scene, printing warnings to stderr. Throws on errors (see run_guarded).
Scene load(const SceneOptions& o, const std::vector<std::string>& extra_overrides = {},
           double frame = 0);

// The next frame of a scene whose animation changes only the view (animates_view_only): its
// camera and settings moved into `loaded` (loaded from the same options), warnings printed.
void load_view_into(const SceneOptions& o, const std::vector<std::string>& extra_overrides,
                    double frame, Scene& loaded);

// "error: MESSAGE" and "warning: MESSAGE" on stderr, the message escaped (math/user_text.h):
// messages quote user text (file names, keys, values), which may hold control characters.
void print_error(const std::string& message);
void print_warning(const std::string& message);

// Runs a command body and turns exceptions into messages and exit codes.
int run_guarded(const std::function<int()>& body);

// Standard output flushed at the end: a failed write there (a closed pipe, a full disk) is an
// error message and exit code 1, not a silent success. Returns the exit code to use.
int flush_standard_output(int code);

// The command line as typed, for metadata.
std::string command_line();
void set_command_line(int argc, char** argv);
const std::vector<std::string>& command_args();  // argv[1..], as given
// A resumed render's arguments are the ones that started it (what its checkpoint names again).
void set_command_args(std::vector<std::string> args);

void add_render(CLI::App& app, std::function<int()>& run);
void add_info(CLI::App& app, std::function<int()>& run);
void add_rays(CLI::App& app, std::function<int()>& run);
void add_project(CLI::App& app, std::function<int()>& run);
void add_formfactors(CLI::App& app, std::function<int()>& run);
void add_bench(CLI::App& app, std::function<int()>& run);
void add_compare(CLI::App& app, std::function<int()>& run);
void add_schema(CLI::App& app, std::function<int()>& run);
void add_serve(CLI::App& app, std::function<int()>& run);
void add_stmap(CLI::App& app, std::function<int()>& run);
void add_warp(CLI::App& app, std::function<int()>& run);
void add_calib(CLI::App& app, std::function<int()>& run);
void add_solve(CLI::App& app, std::function<int()>& run);

}  // namespace anamorph::app
