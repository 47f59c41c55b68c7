// `anamorph render`: render a scene (or a frame range of an animated scene) to its outputs. The
// parts are in files named for their roles (app/render_command.h lists them); this runs them.
#include <memory>

#include "app/interrupt.h"
#include "app/render_command.h"
#include "dist/head.h"
#include "dist/world.h"

namespace anamorph::app {

int run_render(const RenderArgs& a) {
  if (!a.resume.empty()) return resume_render(a);
  RenderSetup s;
  if (const int rc = setup_render(a, &s); rc != kOk) return rc;
  // Under MPI the head (rank 0) goes on below, handing tiles to the workers through its farm.
  std::unique_ptr<dist::HeadFarm> farm;
  if (dist::World::size() > 1 && a.denoise) {
    // The halves' pass tiles are not farmed with their feature layers yet (docs/denoise.md).
    if (dist::World::rank() == 0)
      print_error("--denoise does not run across MPI ranks yet: render it in one process");
    return kBadInput;
  }
  if (dist::World::size() > 1) {
    if (dist::World::rank() > 0) return serve_worker(s);
    farm = std::make_unique<dist::HeadFarm>(s.aovs, &interrupt_flag());
    s.farm = farm.get();
  }
  return a.frames.empty() ? render_single(s) : render_sequence(s);
}

}  // namespace anamorph::app
