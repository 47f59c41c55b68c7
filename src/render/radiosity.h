// Radiosity over whole objects from measured form factors (docs/formfactors.md, "Radiosity"):
// what it needs of the scene, checked before anything is measured, and the solve, whose result is
// checked too: no NaN, infinity or negative radiosity is ever returned.
#pragma once

#include <vector>

#include "accel/accel.h"
#include "render/form_factors.h"
#include "scene/scene.h"

namespace anamorph {

// The diffuse reflectance and emitted radiosity (pi Le) of object `id`'s material.
Color object_reflectance(const Scene& scene, const Accel& accel, uint32_t id);
Color object_emission(const Scene& scene, const Accel& accel, uint32_t id);

// What radiosity over whole objects needs, checked before measuring: every object has a
// measurable surface (a row of form factors), one material with a constant colour and emission,
// a reflectance within [0, 1] per channel and a finite emission. (The scene reader holds keys of
// the scene file to these ranges; models' materials are checked here.) Throws
// std::invalid_argument naming the object, its material and what is wrong. `inward` as
// FormFactorOptions::inward.
void check_radiosity_inputs(const Scene& scene, const Accel& accel,
                            const std::vector<std::string>& inward);

// Radiosity of every object from (I - rho F) B = E (per colour channel), with E = pi Le and rho
// the diffuse reflectance of each object's material, and each pair's A_i F_ij = A_j F_ji taken
// as the inverse-variance mean of its two measurements. Needs every object measured as a row.
// Throws std::invalid_argument when the system has no finite, non-negative solution (a closed
// scene whose surfaces reflect all light: light is never absorbed), saying so.
std::vector<Color> solve_radiosity(const Scene& scene, const Accel& accel, const FormFactors& f);

}  // namespace anamorph
