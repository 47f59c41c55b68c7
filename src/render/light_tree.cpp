#include "render/light_tree.h"

#include <algorithm>
#include <cmath>

namespace anamorph {

namespace {

double safe_sqrt(double x) { return std::sqrt(std::max(0.0, x)); }

// cos(max(0, a - b)) from the sines and cosines of a and b.
double cos_sub_clamped(double sin_a, double cos_a, double sin_b, double cos_b) {
  return cos_a > cos_b ? 1.0 : cos_a * cos_b + sin_a * sin_b;
}

// v turned by angle t about the unit axis k (Rodrigues).
Vec3 rotate(const Vec3& v, const Vec3& k, double t) {
  const double c = std::cos(t), s = std::sin(t);
  return v * c + cross(k, v) * s + k * (dot(k, v) * (1 - c));
}

struct Cone {
  Vec3 w;
  double cos_theta;
};

// The smallest cone holding both (pbrt-v4's DirectionCone union).
Cone cone_union(const Cone& a, const Cone& b) {
  const Cone all{{0, 0, 1}, -1};
  if (a.cos_theta <= -1 || b.cos_theta <= -1) return all;
  const double ta = std::acos(std::clamp(a.cos_theta, -1.0, 1.0));
  const double tb = std::acos(std::clamp(b.cos_theta, -1.0, 1.0));
  const double td = std::atan2(length(cross(a.w, b.w)), dot(a.w, b.w));
  if (std::min(td + tb, kPi) <= ta) return a;
  if (std::min(td + ta, kPi) <= tb) return b;
  const double to = (ta + td + tb) / 2;
  if (to >= kPi) return all;
  const Vec3 wr = cross(a.w, b.w);
  if (!(length_squared(wr) > 0)) return all;
  return {normalize(rotate(a.w, normalize(wr), to - ta)), std::cos(to)};
}

constexpr int kBuckets = 12;

// Which of kBuckets slices of the centroids' box along dim holds centroid c.
int bucket_of(const Vec3& c, const Bounds3& cb, int dim) {
  const double ext = cb.hi[dim] - cb.lo[dim];
  return std::min(kBuckets - 1, int(kBuckets * (c[dim] - cb.lo[dim]) / ext));
}

double surface_area(const Bounds3& b) {
  const Vec3 d = b.diagonal();
  return 2 * (d.x * d.y + d.y * d.z + d.z * d.x);
}

// pbrt-v4's split cost: power times the solid-angle measure of the emission cones times the
// box's area (the cost of descending into it), stretched along thin axes by kr.
double split_cost(const LightBounds& b, double kr) {
  if (!(b.phi > 0)) return 0;
  const double to = std::acos(std::clamp(b.cos_o, -1.0, 1.0));
  const double te = std::acos(std::clamp(b.cos_e, -1.0, 1.0));
  const double tw = std::min(to + te, kPi), sin_o = safe_sqrt(1 - b.cos_o * b.cos_o);
  const double m = 2 * kPi * (1 - b.cos_o) +
                   kPi / 2 * (2 * tw * sin_o - std::cos(to - 2 * tw) - 2 * to * sin_o + b.cos_o);
  return b.phi * m * kr * surface_area(b.box);
}

}  // namespace

double LightBounds::importance(const Vec3& p, const Vec3* n) const {
  return LightCone(*this).importance(p, n);
}

LightCone::LightCone(const LightBounds& b)
    : center(b.box.center()),
      w(b.w),
      r2(length_squared(b.box.diagonal()) * 0.25),
      radius(std::sqrt(r2)),
      phi(b.phi),
      cos_o(b.cos_o),
      sin_o(safe_sqrt(1 - b.cos_o * b.cos_o)),
      cos_e(b.cos_e),
      two_sided(b.two_sided) {}

// pbrt-v4's LightBounds::Importance, with the sines computed only where a cosine is not clamped
// to 1 (most points see most lights within their cones).
double LightCone::importance(const Vec3& p, const Vec3* n) const {
  const Vec3 to_p = p - center;
  const double dist2 = length_squared(to_p);
  const double inv_len = dist2 > 0 ? 1 / std::sqrt(dist2) : 0.0;
  double cos_w = dist2 > 0 ? dot(w, to_p) * inv_len : 1.0;
  if (two_sided) cos_w = std::abs(cos_w);
  // The cone of directions the box takes as seen from p (every direction from inside it).
  double cos_b = -1, sin_b = 0;
  if (dist2 >= r2) {
    sin_b = radius * inv_len;
    cos_b = safe_sqrt(1 - sin_b * sin_b);
  }
  double cos_p = 1;  // of the least angle between p's direction and the emitting cone
  if (cos_w <= cos_o) {
    const double sin_w = safe_sqrt(1 - cos_w * cos_w);
    const double cos_x = cos_w * cos_o + sin_w * sin_o, sin_x = sin_w * cos_o - cos_w * sin_o;
    cos_p = cos_sub_clamped(sin_x, cos_x, sin_b, cos_b);
  }
  if (cos_p <= cos_e) return 0;
  double imp = phi * cos_p / std::max(dist2, r2);  // no closer than the bounding sphere
  if (n) {
    const double cos_i = dist2 > 0 ? std::abs(dot(to_p, *n)) * inv_len : 1.0;
    if (cos_i <= cos_b) imp *= cos_i * cos_b + safe_sqrt(1 - cos_i * cos_i) * sin_b;
  }
  return std::max(imp, 0.0);
}

LightBounds unite(const LightBounds& a, const LightBounds& b) {
  if (!(a.phi > 0)) return b;
  if (!(b.phi > 0)) return a;
  LightBounds r;
  r.box = a.box;
  r.box.extend(b.box);
  r.phi = a.phi + b.phi;
  const Cone c = cone_union({a.w, a.cos_o}, {b.w, b.cos_o});
  r.w = c.w;
  r.cos_o = c.cos_theta;
  r.cos_e = std::min(a.cos_e, b.cos_e);
  r.two_sided = a.two_sided || b.two_sided;
  return r;
}

LightTree::LightTree(const std::vector<LightBounds>& lights) {
  if (lights.empty()) return;
  std::vector<Item> items;
  items.reserve(lights.size());
  for (uint32_t i = 0; i < lights.size(); ++i)
    items.push_back({lights[i], lights[i].box.center(), i});
  leaf_of_.assign(lights.size(), kNone);
  nodes_.reserve(2 * lights.size());
  build(items, 0, items.size(), 0, kNone);
}

uint32_t LightTree::build(std::vector<Item>& items, size_t begin, size_t end, int depth,
                          uint32_t parent) {
  const uint32_t index = uint32_t(nodes_.size());
  nodes_.emplace_back();
  nodes_[index].parent = parent;
  if (end - begin == 1) {
    nodes_[index].bounds = items[begin].bounds;
    nodes_[index].cone = LightCone(items[begin].bounds);
    nodes_[index].child[0] = items[begin].light;
    leaf_of_[items[begin].light] = index;
    return index;
  }
  const size_t mid = split(items, begin, end, depth);
  const uint32_t c0 = build(items, begin, mid, depth + 1, index);
  const uint32_t c1 = build(items, mid, end, depth + 1, index);
  nodes_[index].child[0] = c0;
  nodes_[index].child[1] = c1;
  nodes_[index].bounds = unite(nodes_[c0].bounds, nodes_[c1].bounds);
  nodes_[index].cone = LightCone(nodes_[index].bounds);
  return index;
}

// Where to cut items [begin, end): the cheapest of 12 buckets of centroids along each axis
// (pbrt-v4's cost), or the median along the widest axis when no cut costs anything, the lights
// share one centroid, or the tree is 32 deep (so that no path is longer than kMaxDepth).
size_t LightTree::split(std::vector<Item>& items, size_t begin, size_t end, int depth) const {
  Bounds3 cb;
  LightBounds all;
  for (size_t i = begin; i < end; ++i) {
    cb.extend(items[i].centroid);
    all = unite(all, items[i].bounds);
  }
  const Vec3 ext = cb.diagonal(), diag = all.box.diagonal();
  const double widest = std::max({diag.x, diag.y, diag.z});
  double best = kInf;
  int best_dim = -1, best_cut = 0;
  for (int dim = 0; dim < 3 && depth < 32; ++dim) {
    if (!(ext[dim] > 0)) continue;
    LightBounds b[kBuckets];
    for (size_t i = begin; i < end; ++i) {
      const int k = bucket_of(items[i].centroid, cb, dim);
      b[k] = unite(b[k], items[i].bounds);
    }
    const double kr = widest / diag[dim];
    for (int cut = 1; cut < kBuckets; ++cut) {
      LightBounds lo, hi;
      for (int k = 0; k < cut; ++k) lo = unite(lo, b[k]);
      for (int k = cut; k < kBuckets; ++k) hi = unite(hi, b[k]);
      if (!(lo.phi > 0 && hi.phi > 0)) continue;
      const double cost = split_cost(lo, kr) + split_cost(hi, kr);
      if (cost > 0 && cost < best) best = cost, best_dim = dim, best_cut = cut;
    }
  }
  if (best_dim >= 0) {
    const auto it = std::stable_partition(
        items.begin() + long(begin), items.begin() + long(end),
        [&](const Item& x) { return bucket_of(x.centroid, cb, best_dim) < best_cut; });
    const size_t mid = size_t(it - items.begin());
    if (mid > begin && mid < end) return mid;
  }
  const int dim = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
  const size_t mid = (begin + end) / 2;
  std::nth_element(items.begin() + long(begin), items.begin() + long(mid),
                   items.begin() + long(end), [dim](const Item& a, const Item& b) {
                     return a.centroid[dim] != b.centroid[dim] ? a.centroid[dim] < b.centroid[dim]
                                                               : a.light < b.light;
                   });
  return mid;
}

void LightTree::branch(uint32_t node, const Vec3& p, const Vec3* n, double prob[2]) const {
  const Node& nd = nodes_[node];
  const double i0 = nodes_[nd.child[0]].cone.importance(p, n);
  const double i1 = nodes_[nd.child[1]].cone.importance(p, n);
  const double sum = i0 + i1;
  prob[0] = sum > 0 ? i0 / sum : 0;
  prob[1] = sum > 0 ? i1 / sum : 0;
}

bool LightTree::sample(double u, const Vec3& p, const Vec3* n, uint32_t* light, double* pmf) const {
  if (nodes_.empty()) return false;
  uint32_t node = 0;
  double prob = 1;
  while (!nodes_[node].leaf()) {
    double pc[2];
    branch(node, p, n, pc);
    if (!(pc[0] > 0) && !(pc[1] > 0)) return false;
    const int which = u < pc[0] ? 0 : 1;
    u = std::min(which == 0 ? u / pc[0] : (u - pc[0]) / pc[1], 0x1.fffffffffffffp-1);
    prob *= pc[which];
    node = nodes_[node].child[which];
  }
  *light = nodes_[node].child[0];
  *pmf = prob;
  return prob > 0;
}

double LightTree::pmf(uint32_t light, const Vec3& p, const Vec3* n) const {
  if (light >= leaf_of_.size()) return 0;
  uint32_t path[kMaxDepth + 1];
  int len = 0;
  for (uint32_t node = leaf_of_[light]; nodes_[node].parent != kNone; node = nodes_[node].parent)
    path[len++] = node;
  double prob = 1;
  for (int k = len - 1; k >= 0; --k) {
    const uint32_t parent = nodes_[path[k]].parent;
    double pc[2];
    branch(parent, p, n, pc);
    prob *= pc[nodes_[parent].child[0] == path[k] ? 0 : 1];
    if (!(prob > 0)) return 0;
  }
  return prob;
}

int LightTree::depth() const {
  int deepest = 0;
  for (const uint32_t leaf : leaf_of_) {
    int d = 0;
    for (uint32_t node = leaf; nodes_[node].parent != kNone; node = nodes_[node].parent) ++d;
    deepest = std::max(deepest, d);
  }
  return deepest;
}

}  // namespace anamorph
