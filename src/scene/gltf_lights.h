// glTF's KHR_lights_punctual: reading a node's light, and converting it to a scene Light.
//
// Units (the extension's): point and spot intensity in candela (lm/sr), directional in lux
// (lm/m^2). anamorph's lights are radiometric (W/sr, W/m^2); the conversion divides by
// 683 lm/W, the luminous efficacy at 555 nm that defines the candela (and that Blender's
// exporter multiplies by: W -> cd = W / (4 pi) x 683). Colour multiplies the intensity as given
// (linear RGB). A spot's cone angles are from its axis; its falloff is the extension's
// recommended one unless `cycles_spots` asks for Cycles 3.4's (light.h). Placement: the light
// sits at its node's origin and shines along the node's -z; node scale does not change it.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "scene/light.h"
#include "scene/loaders.h"

namespace tinygltf {
class Model;
class Node;
}  // namespace tinygltf

namespace anamorph {

inline constexpr double kLumensPerWatt = 683;

// The light node `node` holds (KHR_lights_punctual.light), placed at `world`; nullopt when it
// holds none. A reference to a light that does not exist, or an unknown light type, is a
// LoadError; values out of the extension's ranges (negative intensity, cones out of order) are
// clamped into them with a warning.
std::optional<ModelLight> read_node_light(const tinygltf::Model& model, const tinygltf::Node& node,
                                          const std::string& node_name, const Mat4& world,
                                          std::vector<std::string>& warnings);

// The scene light for `l` placed by `world_from_light` (the model's placement times the node's).
Light scene_light(const ModelLight& l, const Transform& world_from_light, bool cycles_spots);

// Moves an existing scene light to `world_from_light` (its position and direction only).
void place_light(Light& light, const Transform& world_from_light);

}  // namespace anamorph
