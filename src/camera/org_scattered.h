// An origin surface through control points placed anywhere in the image (the paper's
// "scattered data interpolation"): radial basis interpolation (math/rbf.h) of [u, v, x, y, z]
// data, with exact first and second derivatives for normals and ray differentials.
#pragma once

#include "camera/functions.h"

namespace anamorph {

extern const OrgFunctionInfo kScatteredOrgInfo;

}  // namespace anamorph
