// `anamorph render`, cut by role. The options and what is worked out from them once
// (render_options.cpp), one frame rendered and reported (render_frame.cpp, its progress line and
// summary in render_progress.cpp, the coin overlay's frame in coin_overlay.cpp), one frame or a
// sequence of them (render_sequence.cpp, frame patterns in frame_pattern.h), the MPI worker
// (render_worker.cpp), --resume (render_resume.cpp), --video (video.h); cmd_render.cpp runs them.
#pragma once

#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/common.h"
#include "app/render_outputs.h"
#include "app/resume_options.h"
#include "render/renderer.h"
#include "render/tile_farm.h"
#include "scene/scene.h"

namespace anamorph::dist {
class HeadFarm;
}

namespace anamorph::app {

// The options as given (add_render declares them).
struct RenderArgs {
  SceneOptions scene;
  std::string output;
  std::optional<int> spp, threads;
  std::optional<int64_t> seed;
  std::optional<std::string> integrator, sampler;
  std::string aovs;
  std::string frames;  // "A:B" or "N"
  std::string video;
  int fps = 30;
  bool coins_overlay = false;  // --aov coins
  bool quiet = false;
  std::string checkpoint;  // --checkpoint FILE (a frame pattern with --frames)
  std::string checkpoint_every = "60s";
  std::string stats;          // --stats FILE (a frame pattern with --frames)
  std::string resume;         // --resume FILE
  ResumeOptions with_resume;  // the other options given with --resume
  bool skip_existing = false;
  bool denoise = false;  // --denoise (render/denoise_film.h)
};

// What the options come to, worked out once for every frame.
struct RenderSetup {
  RenderArgs args;                 // coins_overlay set when --aov names "coins"
  std::vector<std::string> extra;  // --spp, --seed, --integrator, --sampler as scene keys
  std::vector<Aov> aovs;           // the sampled layers (not "coins")
  std::string out;                 // -o or the default; a frame pattern with --frames
  RenderOutputs outs;              // what the outputs are checked against (output_guard.h)
  std::vector<FileRead> scene_file;
  double checkpoint_every = 60;
  dist::HeadFarm* farm = nullptr;  // an MPI job's head: the workers render every tile
};

// render_options.cpp. The setup, or an error printed and kBadInput.
int setup_render(const RenderArgs& a, RenderSetup* s);

// render_progress.cpp. Where a frame stands in its job: frame `index` (from 0) of `count`, the
// job started at `t0`.
struct JobPlace {
  int index = 0, count = 1;
  std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
};
// The progress callback of a frame: a bar on a terminal (`bar`), a line every 10 s in an MPI
// job's log, nothing when quiet.
std::function<void(const Progress&)> progress_printer(const RenderSetup& s,
                                                      const std::string& prefix,
                                                      const JobPlace& place, bool bar);
// The bar's line cleared, for the messages after it.
void clear_progress();
// The frame's summary line (unless quiet) and the NaN warning.
void print_summary(const RenderSetup& s, const std::string& out, const Scene& scene,
                   const RenderStats& st);

// render_frame.cpp. The files of one frame (a sequence's patterns filled in).
struct FrameFiles {
  std::string out, checkpoint, stats;  // checkpoint, stats: empty when not asked for
};
// Renders one frame; returns an exit code.
int render_frame(const RenderSetup& s, const Scene& scene, const Renderer& renderer, double frame,
                 const FrameFiles& files, const std::string& prefix, const JobPlace& place = {});
// Whether --denoise (if given) can denoise this scene's render; if not, says why (the caller exits
// 2 before any allocation or output file).
bool denoise_applies(const RenderSetup& s, const Scene& scene, const std::string& out);
// Whether the machine can hold the render; if not, says why (the caller exits 2 before any
// allocation or output file).
bool fits_in_memory(const RenderSetup& s, const Scene& scene, const std::string& out);

// coin_overlay.cpp. `--aov coins`: the frame kept in a film, written with the coins' layer, and
// the image with the markers drawn in beside it. Returns an exit code.
int render_with_overlay(const RenderSetup& s, const Scene& scene, const Renderer& renderer,
                        double frame, const std::filesystem::path& out, const RenderOptions& opt,
                        RenderStats* st);

// render_sequence.cpp. One frame (no --frames), or frames A..B through the output's pattern.
int render_single(const RenderSetup& s);
int render_sequence(const RenderSetup& s);

// render_worker.cpp. The scene of a sequence's current frame and its renderer. When the keys
// change only camera, image or render settings, the frames share the first one's geometry,
// lights and acceleration structure: only the view is read again. The head and the workers of an
// MPI job load frames through this alike.
struct FrameScene {
  std::unique_ptr<Scene> scene;
  std::unique_ptr<Renderer> renderer;
  // Loads `frame` (and what `aovs` need of the next: attach_next_frame); true when it needs a
  // new renderer (the old one is gone then).
  bool load_frame(const SceneOptions& o, const std::vector<std::string>& extra, double frame,
                  const std::vector<Aov>& aovs);
};
// The head rank of an MPI job renders nothing itself: it builds no acceleration structure.
std::unique_ptr<Renderer> make_renderer(const Scene& scene, const TileFarm* farm);
// A worker rank of an MPI job: loads the frames the head names and renders the tiles it is
// handed. Returns an exit code.
int serve_worker(const RenderSetup& s);

// render_resume.cpp. `render --resume FILE`: the command that started the checkpoint, run again
// (a frame sequence skips the frames it finished), with the options honoured beside --resume.
int resume_render(const RenderArgs& a);

// cmd_render.cpp.
int run_render(const RenderArgs& a);

}  // namespace anamorph::app
