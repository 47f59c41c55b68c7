// Declarations of every preset, for the registry in presets.cpp.
#pragma once

#include "camera/presets.h"

namespace anamorph {

extern const PresetInfo kPerspectivePreset;

}  // namespace anamorph
