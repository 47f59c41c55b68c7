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

// `preset_overridden`: the preset came from --set, so keys of the file's old preset that the new
// one does not know are dropped with a warning instead of being errors.
// The shutter keys: `shutter = [open, close]` (frames, relative to the frame rendered) and
// `rolling_shutter`. The caller builds the rig at open and close (animation) and sets the motion.
struct ShutterSpec {
  double open = 0, close = 0;
  Shutter shutter;
};

std::unique_ptr<Camera> read_camera(const TableReader& r, ImageInfo img,
                                    const std::vector<ModelCamera>& model_cameras,
                                    bool preset_overridden, std::vector<std::string>* warnings,
                                    ShutterSpec* shutter = nullptr);

}  // namespace anamorph
