// Whether what a scene places stays inside the world anamorph renders: every coordinate within
// kMaxCoordinate (math/input_limits.h) once all transforms are composed (an object's, a model's
// node hierarchy), and every placement invertible. The reader turns a problem into an error at
// the key that causes it; nothing beyond reaches the acceleration structure.
#pragma once

#include <string>

#include "math/transform.h"
#include "math/vec.h"
#include "model/mesh.h"

namespace anamorph {

// "" when `object_box` placed by `world_from_object` lies within the world and the placement
// and its inverse are finite; otherwise what is wrong, e.g. "it reaches x = 2e+13, beyond ...".
std::string placement_error(const Transform& world_from_object, const Bounds3& object_box);

// The box of a prototype's vertices in its own space (empty for one without vertices).
Bounds3 prototype_bounds(const Prototype& p);

}  // namespace anamorph
