// Superellipsoid (Barr's superquadric with two exponents).
#pragma once

#include "camera/functions.h"

namespace anamorph {

extern const OrgFunctionInfo kSuperquadricOrgInfo;

}  // namespace anamorph
