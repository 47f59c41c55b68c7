// Builds the scene camera from the [camera] table: a preset, an org/dir composition, or a camera
// found in a loaded model (glTF), plus the rig transform and depth of field.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "camera/camera.h"
#include "camera/presets.h"
#include "camera/virtual_camera.h"
#include "scene/loaders.h"
#include "scene/toml_reader.h"

namespace anamorph {

// What the [camera] table says: the camera's parts (its rig at the frame rendered), depth of
// field, and the shutter interval [open, close] in frames relative to the frame rendered. The
// scene loader reads the table again at open and close for motion blur, then builds the camera.
struct CameraSpec {
  VirtualCameraParts parts;
  DepthOfField dof;
  double shutter_open = 0, shutter_close = 0;
};

// `preset_overridden`: the preset came from --set, so keys of the file's old preset that the new
// one does not know are dropped with a warning instead of being errors.
CameraSpec read_camera(const TableReader& r, ImageInfo img,
                       const std::vector<ModelCamera>& model_cameras, bool preset_overridden,
                       std::vector<std::string>* warnings);

}  // namespace anamorph
