#pragma once

#include <memory>

#include "camera/functions.h"

namespace anamorph {

std::unique_ptr<OrgFunction> make_point_org(Vec3 p);
// Rectangle centered at `center`, spanning edge_u along u and edge_v along v.
std::unique_ptr<OrgFunction> make_plane_org(Vec3 center, Vec3 edge_u, Vec3 edge_v,
                                            ParamRange ur = {}, ParamRange vr = {});

extern const OrgFunctionInfo kPointOrgInfo;
extern const OrgFunctionInfo kPlaneOrgInfo;

}  // namespace anamorph
