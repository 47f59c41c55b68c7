// `render --stats FILE`: what each tile of a frame cost, as JSON, so that cluster renders can be
// planned from real renders (bench/cluster-model simulates rank counts and assignment policies
// from these files).
#pragma once

#include <filesystem>
#include <vector>

#include "render/renderer.h"
#include "scene/scene.h"

namespace anamorph::app {

// Writes the frame's settings, totals and every tile's rectangle, pass, start, duration, samples
// and rays (tiles sorted by pass, then index), atomically.
void write_tile_stats(const std::filesystem::path& file, const Scene& scene, double frame,
                      int threads, const RenderStats& st, std::vector<TileTiming> tiles);

}  // namespace anamorph::app
