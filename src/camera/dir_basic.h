#pragma once

#include <memory>

#include "camera/functions.h"

namespace anamorph {

std::unique_ptr<DirFunction> make_constant_dir(Vec3 d);
// dir(u,v) = S(u,v) - center: any origin function used as a set of directions.
std::unique_ptr<DirFunction> make_surface_dir(std::unique_ptr<OrgFunction> surface, Vec3 center);
// dir = point - org (toward) or org - point (away_from).
std::unique_ptr<DirFunction> make_toward_dir(Vec3 point);
std::unique_ptr<DirFunction> make_away_from_dir(Vec3 point);

extern const DirFunctionInfo kConstantDirInfo;
extern const DirFunctionInfo kFromSurfaceDirInfo;
extern const DirFunctionInfo kTowardDirInfo;
extern const DirFunctionInfo kAwayFromDirInfo;

}  // namespace anamorph
