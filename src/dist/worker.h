// A worker rank: loads each frame the head names, renders the tiles it is handed on its threads
// and sends them back, until the head says stop.
#pragma once

#include <functional>
#include <vector>

#include "render/renderer.h"

namespace anamorph::dist {

// What a worker renders a frame with: the scene loaded for it (kept by the caller until the next
// frame) and the AOV layers of the render.
struct WorkerFrame {
  const Renderer* renderer = nullptr;
  int width = 0, height = 0;
};

// Serves tiles until the head stops the job. `load(frame)` loads a frame (it may throw: the
// message goes to the head, which ends the job). Returns the process's exit code.
int serve_tiles(int threads, const std::vector<Aov>& aovs,
                const std::function<WorkerFrame(double frame)>& load);

}  // namespace anamorph::dist
