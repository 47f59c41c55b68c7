// Deforming meshes on the CPU, per the glTF 2.0 specification: morph targets first (rest +
// sum of weight x target delta, positions and normals), then skinning (each vertex by the
// weighted sum of its joints' matrices, joint matrix = joint's world transform x inverse bind
// matrix; the skinned mesh node's own transform is ignored). Normals go through the blended
// matrix's cofactor (its inverse transpose up to scale) and are normalized; a normal that
// cannot be (zero or not finite) keeps its rest direction.
#pragma once

#include <vector>

#include "model/mesh.h"
#include "scene/gltf_animation.h"
#include "scene/gltf_rig.h"

namespace anamorph {

// The joint matrices of `skin` at `pose` (model space).
std::vector<Mat4> joint_matrices(const Skin& skin, const RigPose& pose);

// One part at morph `weights` and (when `joints` is not null) skinned by those joint matrices:
// writes `positions` and, when the part has normals, `normals` (sized to the part's vertices).
// Positions that come out non-finite (absurd matrices or weights) are set to the origin.
void deform_part(const Deformer::Part& part, const std::vector<double>& weights,
                 const std::vector<Mat4>* joints, std::vector<Vec3f>& positions,
                 std::vector<Vec3f>& normals);

// The deformer's meshes at `pose`, written into `meshes` (the prototype's, one per part).
void deform(const GltfRig& rig, const Deformer& d, const RigPose& pose,
            std::vector<TriangleMesh>& meshes);

}  // namespace anamorph
