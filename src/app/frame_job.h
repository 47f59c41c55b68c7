// One frame of `anamorph render`: its tiles streamed into the output files (or, for per-pixel
// adaptive sampling, a film in passes resolved at the end), a checkpoint kept when asked, and an
// interruption turned into the image so far plus a checkpoint to resume from.
#pragma once

#include <atomic>
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
  // The files written, each by the sink its name chooses (io/image_sink.h: output_files).
  std::vector<std::filesystem::path> files;
  std::map<std::string, std::string> metadata;
  std::filesystem::path checkpoint;  // empty: none
  double checkpoint_every = 60;      // seconds between fsyncs of the checkpoint
  int threads = 0;
  std::function<void(const Progress&)> on_progress;
  std::vector<TileTiming>* tile_times = nullptr;  // --stats
  TileFarm* farm = nullptr;                       // under MPI: the workers render the tiles
  // Stops the render as SIGINT does (the image so far as NAME.partial.EXT); null: SIGINT's flag.
  const std::atomic<bool>* cancel = nullptr;
  // Denoised (render/denoise_film.h): rendered in two halves into a film kept whole (no
  // checkpoint: setup_render refuses one), the beauty denoised before the files are written.
  bool denoise = false;
};

struct FrameResult {
  RenderStats stats;
  bool interrupted = false;
  // Stopped by render.time_limit: the files hold the image so far (whole tiles), the checkpoint
  // is kept, and `reached` says how far it got, e.g. "pass 3 of 6 in 40 of 64 tiles".
  bool time_limited = false;
  std::string reached;
  bool resumed = false;
  size_t resumed_tiles = 0;
  double denoise_seconds = 0;  // > 0: denoised, in this long
};

// The files' metadata: version, command line, scene, camera, frame, and the definition of each
// of `aovs` (anamorph.layer.NAME).
std::map<std::string, std::string> frame_metadata(const Scene& scene, double frame,
                                                  const std::vector<Aov>& aovs = {});

// What a checkpoint of this frame must match: the scene as rendered, the outputs, the AOVs and
// the layers the outputs take.
CheckpointIdentity frame_identity(const FrameJob& job);

// Whether the frame renders in passes over a film kept whole (per-pixel adaptive sampling, and
// uniform sampling with a time limit, so that stopping leaves every pixel with samples) rather
// than streaming each finished tile into the files.
bool renders_in_passes(const RenderSettings& rs);

// Renders the frame into its files. Interrupted: the image so far goes to "<name>.partial.<ext>"
// and the checkpoint (if any) is left to resume; otherwise the files appear and the checkpoint
// is removed. Throws CheckpointError when the checkpoint belongs to another render.
FrameResult render_to_files(const FrameJob& job);

}  // namespace anamorph::app
