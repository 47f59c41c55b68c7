// One frame of `anamorph render`: its tiles streamed into the output files (or, for per-pixel
// adaptive sampling, a film in passes resolved at the end), a checkpoint kept when asked, and an
// interruption turned into the image so far plus a checkpoint to resume from.
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "render/checkpoint.h"
#include "render/renderer.h"
#include "render/tile_buffer.h"
#include "scene/scene.h"

namespace anamorph::app {

struct FrameJob {
  const Scene& scene;
  const Renderer& renderer;
  std::vector<Aov> aovs;
  std::filesystem::path png, exr;  // the files written (either may be empty)
  std::map<std::string, std::string> metadata;
  std::filesystem::path checkpoint;  // empty: none
  double checkpoint_every = 60;      // seconds between fsyncs of the checkpoint
  int threads = 0;
  std::function<void(const Progress&)> on_progress;
};

struct FrameResult {
  RenderStats stats;
  bool interrupted = false;
  bool resumed = false;
  size_t resumed_tiles = 0;
};

// What a checkpoint of this frame must match: the scene as rendered, outputs and AOVs.
CheckpointIdentity frame_identity(const FrameJob& job);

// Renders the frame into its files. Interrupted: the image so far goes to "<name>.partial.<ext>"
// and the checkpoint (if any) is left to resume; otherwise the files appear and the checkpoint
// is removed. Throws CheckpointError when the checkpoint belongs to another render.
FrameResult render_to_files(const FrameJob& job);

}  // namespace anamorph::app
