// Declarations of every preset, for the registry in presets.cpp.
#pragma once

#include "camera/presets.h"

namespace anamorph {

extern const PresetInfo kPerspectivePreset;       // preset_perspective.cpp
extern const PresetInfo kOrthographicPreset;      // preset_orthographic.cpp
extern const PresetInfo kFisheyePreset;           // preset_fisheye.cpp
extern const PresetInfo kMirrorBallPreset;        // preset_fisheye.cpp
extern const PresetInfo kDomePreset;              // preset_fisheye.cpp
extern const PresetInfo kOpenCvPinholePreset;     // preset_opencv.cpp
extern const PresetInfo kOpenCvFisheyePreset;     // preset_opencv.cpp
extern const PresetInfo kEquirectangularPreset;   // preset_cylindrical.cpp
extern const PresetInfo kCylindricalPreset;       // preset_cylindrical.cpp
extern const PresetInfo kMercatorPreset;          // preset_cylindrical.cpp
extern const PresetInfo kLambertEqualAreaPreset;  // preset_cylindrical.cpp
extern const PresetInfo kStereographicPreset;     // preset_stereographic.cpp
extern const PresetInfo kPaniniPreset;            // preset_panini.cpp
extern const PresetInfo kCubemapPreset;           // preset_cubemap.cpp
extern const PresetInfo kOdsPreset;               // preset_ods.cpp
extern const PresetInfo kLightFieldPreset;        // preset_light_field.cpp
extern const PresetInfo kIntegralPreset;          // preset_light_field.cpp
extern const PresetInfo kPushbroomPreset;         // preset_multiperspective.cpp
extern const PresetInfo kCrossedSlitsPreset;      // preset_multiperspective.cpp

}  // namespace anamorph
