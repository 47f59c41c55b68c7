// One frame of `anamorph warp` (its pixels: warp/warp_rows.h), written through the
// output's sink (io/image_sink.h) strip by strip from the top. Only a batch of strips (a few
// per thread) is in memory at once, so an 8K frame costs its source texture's cache and those
// strips, not the whole output (docs/compositing.md, "Memory").
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <string>

#include "warp/warp_rows.h"

namespace anamorph::app {

// The frame written to `file` (its sink chosen by the extension), committed when complete: an
// interruption or error before leaves no file. `progress` (may be empty) gets the fraction done
// after each batch of strips; `committed` (may be empty) runs right after the commit (a sequence
// updates its interruption note there).
void warp_to_file(const WarpView& v, const std::filesystem::path& file,
                  const std::map<std::string, std::string>& metadata,
                  const std::function<void(double)>& progress,
                  const std::function<void()>& committed = nullptr);

}  // namespace anamorph::app
