#pragma once

#include <memory>

#include "camera/functions.h"

namespace anamorph {

std::unique_ptr<DirFunction> make_constant_dir(Vec3 d);
// dir(u,v) = S(u,v) - center: any origin function used as a set of directions.
std::unique_ptr<DirFunction> make_surface_dir(std::unique_ptr<OrgFunction> surface, Vec3 center);

extern const DirFunctionInfo kConstantDirInfo;
extern const DirFunctionInfo kFromSurfaceDirInfo;

}  // namespace anamorph
