// Directions that depend on the origin surface at the same (u, v): normal, tangents, and a
// normal deviated by a constant angle.
#pragma once

#include <memory>

#include "camera/functions.h"

namespace anamorph {

std::unique_ptr<DirFunction> make_normal_dir(bool flip = false);

extern const DirFunctionInfo kNormalDirInfo;
extern const DirFunctionInfo kTangentUDirInfo;
extern const DirFunctionInfo kTangentVDirInfo;
extern const DirFunctionInfo kDeviatedNormalDirInfo;

}  // namespace anamorph
