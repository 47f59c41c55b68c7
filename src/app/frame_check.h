// `render --frames A:B` checks every frame's scene before it renders the first: an [[animate]]
// value out of range at frame 40 is an error before frame 0 is written, naming the entry and the
// frame (docs/robustness.md, "Second probe: honest numbers and messages").
#pragma once

#include <string>
#include <vector>

#include "app/common.h"

namespace anamorph::app {

// Checks frames first..last of the options' scene (with the command's `extra` overrides) as
// they would load; `loaded` is one of them, loaded. Throws SceneError naming the first bad one.
void check_frames(const SceneOptions& o, const std::vector<std::string>& extra, int first, int last,
                  const Scene& loaded);

}  // namespace anamorph::app
