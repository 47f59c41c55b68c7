// Mesh origin function: a triangle mesh's UV layout (Arnold's uv_camera, POV-Ray's mesh_camera).
#pragma once

#include <memory>
#include <string>

#include "camera/functions.h"
#include "scene/loaders.h"

namespace anamorph {

// org(u, v) is the surface point whose texture coordinates are (u', v') = (u_range(u),
// v_range(v)), with the interpolated normal; no ray where no triangle covers (u', v'). Uses
// every mesh with texture coordinates, or only those whose mesh, prototype or instance name is
// `select` (empty = all). Throws ParamError("file" / "select") when nothing usable remains.
std::unique_ptr<OrgFunction> make_mesh_org(const LoadedModel& model, const std::string& select,
                                           ParamRange ur = {}, ParamRange vr = {},
                                           bool flip_normal = false);

extern const OrgFunctionInfo kMeshOrgInfo;

}  // namespace anamorph
