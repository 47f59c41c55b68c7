// Quadric origin surfaces: sphere, ellipsoid, and any quadric through an affine transform.
#pragma once

#include <memory>

#include "camera/functions.h"
#include "camera/org_common.h"

namespace anamorph {

enum class QuadricKind { Sphere, HyperboloidOneSheet, HyperboloidTwoSheets, Paraboloid };

// world = origin + m * X(s, t) for the canonical quadric X of `kind` (see org_quadric.cpp); s is
// the longitude in radians, t the latitude in radians (sphere) or the height parameter.
std::unique_ptr<OrgFunction> make_quadric_org(QuadricKind kind, const Mat3& m, Vec3 origin,
                                              ParamRange s_range, ParamRange t_range,
                                              bool flip_normal);
// Sphere with the default frame (pole +y, longitude 0 at -z); ranges in degrees.
std::unique_ptr<OrgFunction> make_sphere_org(Vec3 center, double radius,
                                             ParamRange longitude = {-180, 180},
                                             ParamRange latitude = {90, -90},
                                             bool flip_normal = false);

extern const OrgFunctionInfo kSphereOrgInfo;
extern const OrgFunctionInfo kEllipsoidOrgInfo;
extern const OrgFunctionInfo kQuadricOrgInfo;

}  // namespace anamorph
