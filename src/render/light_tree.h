// Many lights chosen by what each can give the shading point: a bounding-volume hierarchy over
// the finite emitters (point and spot lights, emissive triangles and spheres) whose nodes bound
// their lights' positions, total power and emission directions (a cone of normals and an
// emission angle beyond it), after Conty Estevez & Kulla, "Importance Sampling of Many Lights
// with Adaptive Tree Splitting" (2018), in the form of pbrt-v4's BVH light sampler. Going down,
// a child is chosen with probability proportional to an estimate of its contribution at p
// (power / distance², times the best cosines its bounds allow at the light and at the surface's
// normal). A light that cannot reach p (p behind a one-sided emitter, outside a spot's cone)
// has probability 0 there. Everything is double precision and deterministic.
#pragma once

#include <cstdint>
#include <vector>

#include "math/vec.h"

namespace anamorph {

struct LightBounds {
  Bounds3 box;             // where the light is
  double phi = 0;          // its power (any consistent measure; only ratios count)
  Vec3 w{0, 0, 1};         // the axis of its emitting normals
  double cos_o = 1;        // cosine of the normals' spread about w (-1: every direction)
  double cos_e = 0;        // cosine of the emission angle beyond the normals (0: a hemisphere)
  bool two_sided = false;  // emits on both sides of its normals
  // The estimate of what the light gives p; n: the shading normal at p, or null (no cosine).
  double importance(const Vec3& p, const Vec3* n) const;
};

// What importance() reads of a LightBounds, with its derived values computed once (a node's).
struct LightCone {
  explicit LightCone(const LightBounds& b);
  LightCone() = default;
  double importance(const Vec3& p, const Vec3* n) const;
  Vec3 center, w;
  double r2 = 0, radius = 0, phi = 0, cos_o = 1, sin_o = 0, cos_e = 0;
  bool two_sided = false;
};

// Bounds of both (the cones' union is the smallest cone holding both; pbrt-v4's).
LightBounds unite(const LightBounds& a, const LightBounds& b);

class LightTree {
 public:
  LightTree() = default;
  explicit LightTree(const std::vector<LightBounds>& lights);

  bool empty() const { return nodes_.empty(); }
  // What all the lights together can give p (the root's bounds), in LightBounds' units.
  double importance(const Vec3& p, const Vec3* n) const {
    return nodes_.empty() ? 0.0 : nodes_[0].cone.importance(p, n);
  }
  // Chooses light *light (an index into the constructor's list) with probability *pmf; false
  // when no light can reach p. A tree of one light always chooses it (pmf 1).
  bool sample(double u, const Vec3& p, const Vec3* n, uint32_t* light, double* pmf) const;
  // The probability that sample() at (p, n) chooses `light`: the same products in the same order.
  double pmf(uint32_t light, const Vec3& p, const Vec3* n) const;
  // Deepest leaf (a test bound: sample and pmf keep a path of at most kMaxDepth nodes).
  int depth() const;
  static constexpr int kMaxDepth = 64;

 private:
  static constexpr uint32_t kNone = ~0u;
  struct Node {
    LightBounds bounds;
    LightCone cone;                      // bounds' importance, fast
    uint32_t child[2] = {kNone, kNone};  // a leaf's light is child[0], with child[1] = kNone
    uint32_t parent = kNone;
    bool leaf() const { return child[1] == kNone; }
  };
  struct Item {
    LightBounds bounds;
    Vec3 centroid;
    uint32_t light;
  };
  uint32_t build(std::vector<Item>& items, size_t begin, size_t end, int depth, uint32_t parent);
  size_t split(std::vector<Item>& items, size_t begin, size_t end, int depth) const;
  // The probabilities of going from `node` to each child at (p, n); 0 and 0 when neither child
  // can reach p.
  void branch(uint32_t node, const Vec3& p, const Vec3* n, double prob[2]) const;

  std::vector<Node> nodes_;
  std::vector<uint32_t> leaf_of_;  // each light's leaf
};

}  // namespace anamorph
