// What a glTF file says about motion, kept beside the loaded model so that any frame can be posed
// without reading the file again: the node hierarchy with each node's own transform, the
// animations' channels and samplers, the skins, and the meshes that deform (skinned or morphed)
// with their rest data. Plain data; gltf_animation.h evaluates it, skinning.h deforms meshes.
//
// Indices: nodes are the file's node indices; `instances`, `cameras`, `lights` and `deformers`
// refer to the LoadedModel's lists of the same names (model space, before a scene places it).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "math/transform.h"
#include "math/vec.h"

namespace anamorph {

// A unit quaternion (x, y, z, w), glTF's order.
struct Quat {
  double x = 0, y = 0, z = 0, w = 1;
};

// Translation, rotation and scale of a node: local = T * R * S.
struct NodeTrs {
  Vec3 t{0, 0, 0};
  Quat r;
  Vec3 s{1, 1, 1};
};

struct RigNode {
  int parent = -1;
  bool has_matrix = false;  // `matrix` given: animation channels cannot target it
  Mat4 matrix = Mat4::identity();
  NodeTrs trs;
  std::vector<double> weights;  // morph target weights at rest (the node's, else its mesh's)
};

enum class Interpolation { Linear, Step, CubicSpline };
enum class AnimPath { Translation, Rotation, Scale, Weights };

// One sampler: key times (seconds, non-decreasing) and `width` values per key (3 translation or
// scale, 4 rotation, the target count for weights), three times as many for CUBICSPLINE
// (in-tangent, value, out-tangent per key).
struct AnimSampler {
  Interpolation interp = Interpolation::Linear;
  std::vector<double> times;
  std::vector<double> values;
  int width = 3;
};

struct AnimChannel {
  int node = 0;
  AnimPath path = AnimPath::Translation;
  uint32_t sampler = 0;    // into GltfRig::samplers (every animation's, concatenated)
  uint32_t animation = 0;  // which animation it belongs to
};

struct Skin {
  std::string name;
  std::vector<int> joints;
  std::vector<Mat4> inverse_bind;  // one per joint (identity when the file gives none)
};

// A mesh node whose vertices move: skinned, or morphed with weights that animate (or differ
// from its mesh's). It has a prototype of its own; each part is one primitive of it (the
// prototype's mesh of the same index), with its rest data.
struct Deformer {
  int node = 0;
  int skin = -1;
  uint32_t prototype = 0;
  bool morph_animated = false;
  struct Part {
    std::vector<Vec3f> positions, normals;                             // rest, before morphing
    std::vector<std::vector<Vec3f>> target_positions, target_normals;  // per morph target
    // Up to 8 influences per vertex (JOINTS_0/1, WEIGHTS_0/1): joint slot in the skin's list
    // and weight, normalized to sum 1 where the sum is positive.
    int influences = 0;
    std::vector<uint16_t> joints;
    std::vector<float> weights;
  };
  std::vector<Part> parts;
};

struct GltfRig {
  std::vector<RigNode> nodes;
  std::vector<int> order;  // parents before children (every node)
  std::vector<AnimSampler> samplers;
  std::vector<AnimChannel> channels;
  std::vector<std::string> animations;  // names, in the file's order
  std::vector<Skin> skins;
  std::vector<Deformer> deformers;
  // The node each of the LoadedModel's instances, cameras and lights belongs to (a skinned
  // mesh's instance: its node too, though its transform is the skeleton's, in `deformers`).
  std::vector<int> instance_nodes, camera_nodes, light_nodes;
  std::vector<bool> instance_skinned;  // placed by its skin: model space, identity transform
  // Per node: its world transform changes over time (it or an ancestor is animated).
  std::vector<bool> moving;
  double start = 0, end = 0;  // the animations' time range (seconds)

  bool animated() const { return !channels.empty(); }
};

}  // namespace anamorph
