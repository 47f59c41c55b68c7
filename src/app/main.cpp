// anamorph: a ray tracer built around a programmable distortion camera.
#include <CLI/CLI.hpp>

#include <functional>

#include "app/common.h"

int main(int argc, char** argv) {
  using namespace anamorph::app;
  set_command_line(argc, argv);
  install_interrupt_handlers();
  CLI::App app{"anamorph " ANAMORPH_VERSION
               " - a ray tracer built around a programmable distortion camera"};
  app.set_version_flag("--version", "anamorph " ANAMORPH_VERSION);
  app.require_subcommand(1);
  std::function<int()> run;
  add_render(app, run);
  add_info(app, run);
  add_rays(app, run);
  add_project(app, run);
  add_formfactors(app, run);
  add_bench(app, run);
  add_compare(app, run);
  add_schema(app, run);
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return kBadInput;
  }
  return run_guarded(run);
}
