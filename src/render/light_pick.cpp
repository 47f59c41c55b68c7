// Lights::pick: which light a shading point samples. The lights at infinity (directional, the
// environment) and the finite lights as one group are chosen by estimated power, in the order
// the emitters were added (the group where its first light is); within the group the light tree
// chooses by what each light can give the point. One finite light is always chosen with the
// group (the tree of one light), so a scene with one light picks as it did before the tree.
#include <algorithm>

#include "render/lights.h"

namespace anamorph {

LightBounds Lights::bounds_of(const Emitter& e, double power) const {
  LightBounds b;
  b.phi = power;
  switch (e.kind) {
    case Emitter::Kind::Point:
      b.box.extend(e.p0);
      b.cos_o = -1;  // every direction
      break;
    case Emitter::Kind::Spot:
      b.box.extend(e.p0);
      b.w = e.dir;
      b.cos_e = e.cos_outer;  // nothing beyond the outer cone (punctual_factor)
      break;
    case Emitter::Kind::Triangle:
      b.box.extend(e.p0);
      b.box.extend(e.p1);
      b.box.extend(e.p2);
      b.w = normalize(cross(e.p1 - e.p0, e.p2 - e.p0));  // the side sample_triangle lights
      b.two_sided = e.two_sided;
      break;
    default:  // a sphere
      b.box.extend(e.p0 - Vec3(e.radius, e.radius, e.radius));
      b.box.extend(e.p0 + Vec3(e.radius, e.radius, e.radius));
      b.cos_o = -1;
      break;
  }
  return b;
}

void Lights::build_pick(const std::vector<double>& power) {
  std::vector<double> group_power;
  std::vector<LightBounds> finite;
  uint32_t tree_group = kInTree;
  group_of_.assign(emitters_.size(), 0);
  tree_slot_.assign(emitters_.size(), kInTree);
  for (uint32_t i = 0; i < emitters_.size(); ++i) {
    const auto k = emitters_[i].kind;
    if (k == Emitter::Kind::Directional || k == Emitter::Kind::Environment) {
      group_of_[i] = uint32_t(group_power.size());
      group_emitter_.push_back(i);
      group_power.push_back(power[i]);
      continue;
    }
    if (tree_group == kInTree) {
      tree_group = uint32_t(group_power.size());
      group_emitter_.push_back(kInTree);
      group_power.push_back(0);
    }
    group_of_[i] = tree_group;
    group_power[tree_group] += power[i];
    tree_slot_[i] = uint32_t(finite.size());
    tree_emitter_.push_back(i);
    finite.push_back(bounds_of(emitters_[i], power[i]));
  }
  groups_ = Distribution1D(group_power);
  tree_ = LightTree(finite);
}

bool Lights::pick(double u, const Vec3& p, const Vec3& n, size_t* index, double* pmf) const {
  if (groups_.size() == 0) return false;
  double gp;
  const size_t g = groups_.sample_discrete(u, &gp);
  if (group_emitter_[g] != kInTree) {
    *index = group_emitter_[g];
    *pmf = gp;
    return gp > 0;
  }
  const double v = std::min((u - groups_.cdf(g)) / gp, 0x1.fffffffffffffp-1);
  uint32_t slot;
  double tp;
  if (!(gp > 0 && tree_.sample(std::max(0.0, v), p, &n, &slot, &tp))) return false;
  *index = tree_emitter_[slot];
  *pmf = gp * tp;
  return true;
}

double Lights::pick_pmf(size_t i, const Vec3& p, const Vec3& n) const {
  const double gp = groups_.pmf(group_of_[i]);
  if (tree_slot_[i] == kInTree) return gp;
  return gp * tree_.pmf(tree_slot_[i], p, &n);
}

}  // namespace anamorph
