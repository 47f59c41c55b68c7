// anamorph: a ray tracer built around a programmable distortion camera.
#include <oneapi/tbb/global_control.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <functional>
#include <string>

#include "app/common.h"
#include "dist/world.h"
#include "math/simd.h"
#include "math/user_text.h"

namespace {

int run_main(int argc, char** argv) {
  using namespace anamorph::app;
  set_command_line(argc, argv);
  install_interrupt_handlers();
  CLI::App app{"anamorph " ANAMORPH_VERSION
               " - a ray tracer built around a programmable distortion camera"};
  app.set_version_flag("--version", std::string("anamorph " ANAMORPH_VERSION " (MPI: ") +
                                        anamorph::dist::mpi_library() + ")");
  app.require_subcommand(1);
  // Parse errors quote the arguments: escaped, as every message that echoes user text
  // (subcommands take this from the app when they are added).
  app.failure_message([](const CLI::App* a, const CLI::Error& e) {
    std::string text = CLI::FailureMessage::simple(a, e), out;
    for (size_t s = 0, n; s < text.size(); s = n + 1) {
      n = std::min(text.find('\n', s), text.size());
      out += anamorph::printable(std::string_view(text).substr(s, n - s)) + "\n";
    }
    return out;
  });
  std::function<int()> run;
  add_render(app, run);
  add_info(app, run);
  add_rays(app, run);
  add_project(app, run);
  add_formfactors(app, run);
  add_bench(app, run);
  add_compare(app, run);
  add_schema(app, run);
  add_serve(app, run);
  add_stmap(app, run);
  add_warp(app, run);
  add_calib(app, run);
  add_solve(app, run);
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return kBadInput;
  }
  if (anamorph::dist::World::size() > 1 && !app.got_subcommand("render")) {
    if (anamorph::dist::World::rank() == 0)
      std::fputs("error: only `anamorph render` runs across MPI ranks\n", stderr);
    return kBadInput;
  }
  // The kernels' instruction set (math/simd.h): an ANAMORPH_ISA that names none, or one this CPU
  // lacks, is refused rather than measured as something else.
  if (const std::string problem = anamorph::simd::override_problem(); !problem.empty()) {
    std::fprintf(stderr, "error: %s\n", anamorph::printable(problem).c_str());
    return kBadInput;
  }
  return flush_standard_output(run_guarded(run));
}

}  // namespace

int main(int argc, char** argv) {
  const anamorph::dist::World world(&argc, &argv);  // MPI, under mpirun
  // The worker threads are joined before the process exits rather than told to stop while it
  // exits: threads ending during exit raced LeakSanitizer's final check ("Tracer caught signal
  // 11") and would race any other at-exit work the same way.
  tbb::task_scheduler_handle workers{tbb::attach{}};
  const int code = run_main(argc, argv);
  (void)tbb::finalize(workers, std::nothrow);
  return code;
}
