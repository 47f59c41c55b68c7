// Surfaces of revolution around an axis: cylinder, cone, torus.
#pragma once

#include "camera/functions.h"

namespace anamorph {

extern const OrgFunctionInfo kCylinderOrgInfo;
extern const OrgFunctionInfo kConeOrgInfo;
extern const OrgFunctionInfo kTorusOrgInfo;

}  // namespace anamorph
