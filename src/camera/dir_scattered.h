// Direction fields through scattered direction samples: `scattered` interpolates directions
// over the image (u, v); `scattered_sphere` pulls a base layout of the sphere of directions
// (fisheye or equirectangular) toward given directions, interpolating over the sphere itself
// with chordal distances (Pottmann & Eck). Both by radial basis functions (math/rbf.h).
#pragma once

#include "camera/functions.h"

namespace anamorph {

extern const DirFunctionInfo kScatteredDirInfo;
extern const DirFunctionInfo kScatteredSphereDirInfo;

}  // namespace anamorph
