// Evaluating a glTF rig (gltf_rig.h) at a time, per the glTF 2.0 specification (section 3.11,
// Appendix C): LINEAR (quaternions by spherical linear interpolation along the shorter arc),
// STEP, and CUBICSPLINE (cubic Hermite with the file's tangents, scaled by the key interval);
// before the first key and after the last the value is held. Rotations are normalized after
// interpolation. Then node world transforms down the hierarchy, and morph weights per node.
#pragma once

#include <vector>

#include "scene/gltf_rig.h"

namespace anamorph {

// The sampler's value at time t (`width` numbers).
std::vector<double> sample_at(const AnimSampler& s, double t);

// Spherical linear interpolation from a to b (the shorter way round), u in [0, 1].
Quat slerp(Quat a, Quat b, double u);
Quat normalized(Quat q);
Mat4 rotation_matrix(const Quat& q);
Mat4 trs_matrix(const NodeTrs& trs);

// Every node's transform (model space, i.e. the file's root space) and morph weights at t
// (`animate` false: the nodes as the file writes them, its static pose).
struct RigPose {
  std::vector<Mat4> world;
  std::vector<std::vector<double>> weights;
};
RigPose pose_rig(const GltfRig& rig, double t, bool animate = true);

}  // namespace anamorph
