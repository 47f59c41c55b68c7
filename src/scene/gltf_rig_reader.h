// Reading a glTF file's motion into a GltfRig (gltf_rig.h): nodes, animations, skins, and the
// rest data of deforming primitives. The glTF loader calls these; the rig's bindings
// (instances, cameras, lights, deformers) are filled as it places the nodes.
//
// Strictness: what would make the model wrong to draw is a LoadError (a skin naming a node
// that does not exist); what only leaves motion out is a warning and the part is skipped (a
// channel whose sampler is malformed, key times that go backwards, a channel on a node given
// by `matrix`, which glTF forbids).
#pragma once

#include <string>
#include <vector>

#include "scene/gltf_rig.h"

namespace tinygltf {
class Model;
struct Primitive;
}  // namespace tinygltf

namespace anamorph {

// Nodes (parents, rest transforms, morph weights), every animation and every skin. Node
// indices were checked by the loader (a tree, every child exists).
GltfRig read_rig(const tinygltf::Model& model, std::vector<std::string>& warnings);

// Rest data of one primitive of a deforming node: positions and normals before morphing
// (`repaired_normals` stand in where the file's normal is zero or not finite), morph targets,
// and, with `skin`, the joints and weights of every vertex (weights normalized).
Deformer::Part read_deformer_part(const tinygltf::Model& model, const tinygltf::Primitive& pr,
                                  const std::vector<Vec3f>& repaired_normals, const Skin* skin,
                                  std::vector<std::string>& warnings);

// After the nodes are placed: which nodes move (animated themselves or below one that is), and
// the animations' time range.
void finish_rig(GltfRig& rig);

}  // namespace anamorph
