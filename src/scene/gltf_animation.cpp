#include "scene/gltf_animation.h"

#include <algorithm>
#include <cmath>

namespace anamorph {

namespace {

// The key interval holding t: times[k] <= t < times[k + 1] (t strictly inside the range).
size_t interval(const std::vector<double>& times, double t) {
  const auto it = std::upper_bound(times.begin(), times.end(), t);
  return size_t(it - times.begin()) - 1;
}

// Element k's `width` numbers of a sampler's values, at `offset` within the key (CUBICSPLINE:
// 0 in-tangent, 1 value, 2 out-tangent).
const double* element(const AnimSampler& s, size_t k, int offset) {
  const size_t per_key = s.interp == Interpolation::CubicSpline ? 3 : 1;
  return s.values.data() + (k * per_key + size_t(offset)) * size_t(s.width);
}

bool is_rotation(const AnimSampler& s) { return s.width == 4; }

}  // namespace

Quat normalized(Quat q) {
  const double n = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
  if (!(n > 0) || !std::isfinite(n)) return Quat{};
  return {q.x / n, q.y / n, q.z / n, q.w / n};
}

Quat slerp(Quat a, Quat b, double u) {
  double d = a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w;
  if (d < 0) {  // the shorter arc
    b = {-b.x, -b.y, -b.z, -b.w};
    d = -d;
  }
  double wa = 1 - u, wb = u;
  if (d < 1 - 1e-9) {
    const double theta = std::acos(std::min(d, 1.0)), s = std::sin(theta);
    wa = std::sin((1 - u) * theta) / s;
    wb = std::sin(u * theta) / s;
  }
  return normalized(
      {wa * a.x + wb * b.x, wa * a.y + wb * b.y, wa * a.z + wb * b.z, wa * a.w + wb * b.w});
}

std::vector<double> sample_at(const AnimSampler& s, double t) {
  const size_t w = size_t(s.width), n = s.times.size();
  std::vector<double> out(w, 0.0);
  if (n == 0) return out;
  const int value_at = s.interp == Interpolation::CubicSpline ? 1 : 0;
  const auto copy = [&](size_t k) {
    const double* v = element(s, k, value_at);
    std::copy(v, v + w, out.begin());
  };
  if (!(t > s.times.front())) {
    copy(0);
  } else if (!(t < s.times.back())) {
    copy(n - 1);
  } else {
    const size_t k = interval(s.times, t);
    const double td = s.times[k + 1] - s.times[k];
    const double u = td > 0 ? (t - s.times[k]) / td : 1;
    if (s.interp == Interpolation::Step) {
      copy(k);
    } else if (s.interp == Interpolation::Linear) {
      const double *a = element(s, k, 0), *b = element(s, k + 1, 0);
      if (is_rotation(s)) {
        const Quat q = slerp({a[0], a[1], a[2], a[3]}, {b[0], b[1], b[2], b[3]}, u);
        out = {q.x, q.y, q.z, q.w};
      } else {
        for (size_t c = 0; c < w; ++c) out[c] = a[c] + (b[c] - a[c]) * u;
      }
    } else {
      // Hermite: p = h00 v_k + h10 td b_k + h01 v_k+1 + h11 td a_k+1.
      const double u2 = u * u, u3 = u2 * u;
      const double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2,
                   h11 = u3 - u2;
      const double *v0 = element(s, k, 1), *b0 = element(s, k, 2), *a1 = element(s, k + 1, 0),
                   *v1 = element(s, k + 1, 1);
      for (size_t c = 0; c < w; ++c)
        out[c] = h00 * v0[c] + h10 * td * b0[c] + h01 * v1[c] + h11 * td * a1[c];
    }
  }
  if (is_rotation(s)) {
    const Quat q = normalized({out[0], out[1], out[2], out[3]});
    out = {q.x, q.y, q.z, q.w};
  }
  return out;
}

Mat4 rotation_matrix(const Quat& q0) {
  const Quat q = normalized(q0);
  const double x = q.x, y = q.y, z = q.z, w = q.w;
  Mat4 r = Mat4::identity();
  r.m[0][0] = 1 - 2 * (y * y + z * z);
  r.m[0][1] = 2 * (x * y - z * w);
  r.m[0][2] = 2 * (x * z + y * w);
  r.m[1][0] = 2 * (x * y + z * w);
  r.m[1][1] = 1 - 2 * (x * x + z * z);
  r.m[1][2] = 2 * (y * z - x * w);
  r.m[2][0] = 2 * (x * z - y * w);
  r.m[2][1] = 2 * (y * z + x * w);
  r.m[2][2] = 1 - 2 * (x * x + y * y);
  return r;
}

Mat4 trs_matrix(const NodeTrs& trs) {
  Mat4 m = rotation_matrix(trs.r);
  const double s[3] = {trs.s.x, trs.s.y, trs.s.z};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m.m[r][c] *= s[c];
  m.m[0][3] = trs.t.x;
  m.m[1][3] = trs.t.y;
  m.m[2][3] = trs.t.z;
  return m;
}

RigPose pose_rig(const GltfRig& rig, double t, bool animate) {
  const size_t n = rig.nodes.size();
  std::vector<NodeTrs> local(n);
  RigPose pose;
  pose.weights.resize(n);
  for (size_t i = 0; i < n; ++i) {
    local[i] = rig.nodes[i].trs;
    pose.weights[i] = rig.nodes[i].weights;
  }
  for (const AnimChannel& c : animate ? rig.channels : std::vector<AnimChannel>{}) {
    const std::vector<double> v = sample_at(rig.samplers[c.sampler], t);
    NodeTrs& l = local[size_t(c.node)];
    switch (c.path) {
      case AnimPath::Translation:
        l.t = {v[0], v[1], v[2]};
        break;
      case AnimPath::Rotation:
        l.r = {v[0], v[1], v[2], v[3]};
        break;
      case AnimPath::Scale:
        l.s = {v[0], v[1], v[2]};
        break;
      case AnimPath::Weights: {
        std::vector<double>& w = pose.weights[size_t(c.node)];
        w.resize(std::max(w.size(), v.size()), 0.0);
        std::copy(v.begin(), v.end(), w.begin());
        break;
      }
    }
  }
  pose.world.assign(n, Mat4::identity());
  for (const int i : rig.order) {
    const RigNode& node = rig.nodes[size_t(i)];
    const Mat4 m = node.has_matrix ? node.matrix : trs_matrix(local[size_t(i)]);
    pose.world[size_t(i)] = node.parent >= 0 ? pose.world[size_t(node.parent)] * m : m;
  }
  return pose;
}

}  // namespace anamorph
