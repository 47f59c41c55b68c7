// Lights::pick: which light a shading point samples. First among the groups, in the order the
// emitters were added (the finite lights' group where its first light is): each light at
// infinity (directional, the environment) and the finite lights as one group, in proportion to
// what each can give the point, in the light tree's units (a point light of intensity I gives
// 4 pi I cos / d^2; a directional light of irradiance E is weighed as 4 pi E |cos|, an
// environment of mean radiance L as 4 pi pi L, a constant one at a quarter of it). Then within
// the group the tree chooses. A scene
// with one light picks it with probability 1, as before the tree.
#include <algorithm>
#include <cmath>

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
  std::vector<LightBounds> finite;
  uint32_t tree_group = kInTree;
  group_of_.assign(emitters_.size(), 0);
  tree_slot_.assign(emitters_.size(), kInTree);
  for (uint32_t i = 0; i < emitters_.size(); ++i) {
    const auto k = emitters_[i].kind;
    if (k == Emitter::Kind::Directional || k == Emitter::Kind::Environment) {
      group_of_[i] = uint32_t(group_emitter_.size());
      group_emitter_.push_back(i);
      continue;
    }
    if (tree_group == kInTree) {
      tree_group = uint32_t(group_emitter_.size());
      group_emitter_.push_back(kInTree);
    }
    group_of_[i] = tree_group;
    tree_slot_[i] = uint32_t(finite.size());
    tree_emitter_.push_back(i);
    finite.push_back(bounds_of(emitters_[i], power[i]));
  }
  tree_ = LightTree(finite);
}

double Lights::group_weight(size_t g, const Vec3& p, const Vec3& n) const {
  const uint32_t e = group_emitter_[g];
  if (e == kInTree) return tree_.importance(p, &n);
  const Emitter& em = emitters_[e];
  if (em.kind == Emitter::Kind::Directional)
    return 4 * kPi * luminance(em.L) * std::abs(dot(n, em.dir));
  // A constant sky at a quarter of that: BSDF sampling finds it as well (MIS), while delta and
  // small lights are found only here (examples/paper/world.toml: display RMSE 0.0107 at the
  // full weight, 0.0097 at a quarter); an image may hold a small bright sun: full weight.
  return (scene_.environment.image ? 1.0 : 0.25) * 4 * kPi * kPi * env_luminance_;
}

double Lights::group_total(const Vec3& p, const Vec3& n) const {
  double total = 0;
  for (size_t g = 0; g < group_emitter_.size(); ++g) total += group_weight(g, p, n);
  return total;
}

bool Lights::pick(double u, const Vec3& p, const Vec3& n, size_t* index, double* pmf) const {
  const size_t groups = group_emitter_.size();
  const double total = groups > 1 ? group_total(p, n) : 1.0;
  if (!(total > 0)) return false;
  double below = 0, w = 1;
  size_t g = 0;
  for (; groups > 1 && g < groups; ++g) {  // (one group: chosen with probability 1, u as it is)
    w = group_weight(g, p, n);
    if (u * total < below + w || g + 1 == groups) break;
    below += w;
  }
  const double gp = groups > 1 ? w / total : 1.0;
  if (!(gp > 0)) return false;
  if (group_emitter_[g] != kInTree) {
    *index = group_emitter_[g];
    *pmf = gp;
    return true;
  }
  const double v = groups > 1 ? std::clamp((u * total - below) / w, 0.0, 0x1.fffffffffffffp-1) : u;
  uint32_t slot;
  double tp;
  if (!tree_.sample(v, p, &n, &slot, &tp)) return false;
  *index = tree_emitter_[slot];
  *pmf = gp * tp;
  return true;
}

double Lights::pick_pmf(size_t i, const Vec3& p, const Vec3& n) const {
  const size_t g = group_of_[i];
  const double gp = group_emitter_.size() > 1 ? group_weight(g, p, n) / group_total(p, n) : 1.0;
  if (!(gp > 0) || tree_slot_[i] == kInTree) return std::isfinite(gp) ? gp : 0.0;
  return gp * tree_.pmf(tree_slot_[i], p, &n);
}

}  // namespace anamorph
