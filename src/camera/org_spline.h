// Free-form origin surfaces from control nets: bezier, bspline, nurbs.
#pragma once

#include <memory>

#include "camera/functions.h"
#include "camera/spline_surface.h"

namespace anamorph {

// A spline surface as an origin function; u_range / v_range are fractions of the valid domain.
std::unique_ptr<OrgFunction> make_spline_org(SplineSurface surface, ParamRange ur = {},
                                             ParamRange vr = {}, bool flip_normal = false);

extern const OrgFunctionInfo kBezierOrgInfo;
extern const OrgFunctionInfo kBSplineOrgInfo;
extern const OrgFunctionInfo kNurbsOrgInfo;

}  // namespace anamorph
