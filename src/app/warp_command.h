// `anamorph warp`'s pieces: its arguments, one frame (cmd_warp.cpp) and a --frames sequence of
// printf-numbered inputs and outputs with the scene's [[animate]] keys evaluated per frame
// (warp_sequence.cpp).
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "app/common.h"

namespace anamorph::app {

struct WarpArgs {
  SceneOptions scene;
  std::string input, source, output, filter = "area", frames;
  std::optional<int> threads;
  bool quiet = false;
};

// `input` read, checked against --source, warped through the camera of `s` into `output`
// (streamed in strips, committed complete). `prefix` starts the progress bar ("frame 3 (2 of
// 5) "); `committed` runs once the output is there. Throws on bad input (exit 2) and failures
// (exit 1).
void warp_frame(const WarpArgs& a, const Scene& s, const std::filesystem::path& input,
                const std::filesystem::path& output, const std::string& prefix,
                const std::function<void()>& committed = nullptr);

// --frames A:B: INPUT and -o are printf patterns; every input frame must exist (a gap is exit 2,
// named, before anything is written).
int warp_sequence(const WarpArgs& a);

}  // namespace anamorph::app
