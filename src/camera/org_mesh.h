// Mesh origin function: a triangle mesh's UV layout (Arnold's uv_camera, POV-Ray's mesh_camera).
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "camera/functions.h"
#include "model/mesh.h"

namespace anamorph {

// org(u, v) is the surface point whose texture coordinates are (u', v') = (u_range(u),
// v_range(v)), with the interpolated normal; no ray where no triangle covers (u', v'). Uses
// every mesh with texture coordinates, or only those whose mesh, prototype or instance name is
// `select` (empty = all). Throws ParamError("file" / "select") when nothing usable remains.
std::unique_ptr<OrgFunction> make_mesh_org(std::span<const Prototype> prototypes,
                                           std::span<const Instance> instances,
                                           const std::string& select, ParamRange ur = {},
                                           ParamRange vr = {}, bool flip_normal = false);

// How `type = "mesh"` reads its file: the model loaders live above camera/ (in scene/, which
// installs them here when it is linked), so camera/ depends on none of them. Throws on failure.
using MeshFileReader = void (*)(const std::string& file, std::vector<Prototype>* prototypes,
                                std::vector<Instance>* instances);
void set_mesh_file_reader(MeshFileReader reader);

extern const OrgFunctionInfo kMeshOrgInfo;

}  // namespace anamorph
