// The files one frame of `anamorph render` may write, named as the user knows them, for the
// check that none of them is an input of the run or another of its outputs (app/output_guard.h);
// and where a render without -o writes.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "io/image_sink.h"
#include "io/read_log.h"

namespace anamorph::app {

// A render without -o writes out/<scene name>.png under the current directory (out/ is created;
// the repository ignores it), out/<scene name>_%04d.png with --frames.
std::string default_render_output(const std::filesystem::path& scene, bool frames);

// `--aov coins`: the image with the coins' markers drawn in, beside the output (out.coins.png).
std::filesystem::path coin_overlay_file(const std::filesystem::path& out);

struct RenderOutputs {
  std::filesystem::path out;  // the image (-o, or the default)
  bool default_output = false;
  std::vector<LayerSpec> layers;  // what the render writes: the beauty, the AOVs, the coins
  bool coins_overlay = false;     // --aov coins
  std::filesystem::path checkpoint, stats, video;
  std::string frame;  // " (frame N)" in a sequence, else ""
};

// Every file the frame writes, or may write (the image so far when interrupted), each with its
// description: "-o out.png", "the AOVs' EXR out.exr (written beside -o out.png)", ...
std::vector<std::pair<std::filesystem::path, std::string>> render_output_files(
    const RenderOutputs& o);

// Throws OutputClash when a file of render_output_files(o) is one of `inputs` (the scene's
// inputs; before the load, the scene file alone), another of them, read-only or a directory.
void check_render_outputs(const RenderOutputs& o, const std::vector<FileRead>& inputs);

}  // namespace anamorph::app
