// Origin and direction functions given as sampled tables (camera/ray_table.h): `table` reads an
// EXR that `anamorph rays -o rays.exr` wrote (or any EXR with such a layer) or takes the grid
// inline, so a measured lens, a generic calibration or any camera's own ray field is a camera.
#pragma once

#include <string>

#include "camera/functions.h"
#include "camera/ray_table.h"

namespace anamorph {

// How `file` is read: the EXR reader lives in io/, above camera/, and scene/ installs it here.
// Reads layer `layer` (channels LAYER.X, .Y, .Z, refined by LAYER_lo.X/Y/Z when present, and
// validity from valid.V when present). Throws with a message on failure.
using RayTableFileReader = RayTableData (*)(const std::string& file, const std::string& layer);
void set_ray_table_file_reader(RayTableFileReader reader);

extern const OrgFunctionInfo kTableOrgInfo;
extern const DirFunctionInfo kTableDirInfo;

}  // namespace anamorph
