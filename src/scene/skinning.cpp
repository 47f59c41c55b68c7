#include "scene/skinning.h"

#include <cmath>

namespace anamorph {

namespace {

bool finite(const Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// The 3x3 cofactor matrix of m's linear part applied to n: (det m) m^-T n, without dividing.
Vec3 cofactor_times(const Mat4& m, const Vec3& n) {
  const auto& a = m.m;
  const Vec3 c0{a[1][1] * a[2][2] - a[1][2] * a[2][1], a[1][2] * a[2][0] - a[1][0] * a[2][2],
                a[1][0] * a[2][1] - a[1][1] * a[2][0]};
  const Vec3 c1{a[0][2] * a[2][1] - a[0][1] * a[2][2], a[0][0] * a[2][2] - a[0][2] * a[2][0],
                a[0][1] * a[2][0] - a[0][0] * a[2][1]};
  const Vec3 c2{a[0][1] * a[1][2] - a[0][2] * a[1][1], a[0][2] * a[1][0] - a[0][0] * a[1][2],
                a[0][0] * a[1][1] - a[0][1] * a[1][0]};
  return c0 * n.x + c1 * n.y + c2 * n.z;
}

Vec3 apply(const Mat4& m, const Vec3& p) {
  const auto& a = m.m;
  return {a[0][0] * p.x + a[0][1] * p.y + a[0][2] * p.z + a[0][3],
          a[1][0] * p.x + a[1][1] * p.y + a[1][2] * p.z + a[1][3],
          a[2][0] * p.x + a[2][1] * p.y + a[2][2] * p.z + a[2][3]};
}

}  // namespace

std::vector<Mat4> joint_matrices(const Skin& skin, const RigPose& pose) {
  std::vector<Mat4> j(skin.joints.size());
  for (size_t i = 0; i < j.size(); ++i)
    j[i] = pose.world[size_t(skin.joints[i])] * skin.inverse_bind[i];
  return j;
}

void deform_part(const Deformer::Part& part, const std::vector<double>& weights,
                 const std::vector<Mat4>* joints, std::vector<Vec3f>& positions,
                 std::vector<Vec3f>& normals) {
  const size_t n = part.positions.size();
  const bool has_normals = !part.normals.empty();
  positions.resize(n);
  normals.resize(has_normals ? n : 0);
  for (size_t v = 0; v < n; ++v) {
    Vec3 p(part.positions[v]);
    Vec3 nr = has_normals ? Vec3(part.normals[v]) : Vec3{};
    for (size_t t = 0; t < weights.size() && t < part.target_positions.size(); ++t) {
      const double w = weights[t];
      if (w == 0) continue;
      if (!part.target_positions[t].empty()) p += Vec3(part.target_positions[t][v]) * w;
      if (has_normals && !part.target_normals[t].empty()) nr += Vec3(part.target_normals[t][v]) * w;
    }
    if (joints && part.influences > 0) {
      Mat4 m;  // the blended matrix (zero)
      double total = 0;
      for (int k = 0; k < part.influences; ++k) {
        const size_t at = v * size_t(part.influences) + size_t(k);
        const double w = part.weights[at];
        if (w == 0) continue;
        const Mat4& j = (*joints)[part.joints[at]];
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 4; ++c) m.m[r][c] += w * j.m[r][c];
        total += w;
      }
      if (total > 0) {
        p = apply(m, p);
        if (has_normals) nr = cofactor_times(m, nr);
      }
    }
    positions[v] = finite(p) ? Vec3f(p) : Vec3f(0, 0, 0);
    if (has_normals) {
      const double len = length(nr);
      normals[v] = len > 0 && std::isfinite(len) ? Vec3f(nr / len) : part.normals[v];
    }
  }
}

void deform(const GltfRig& rig, const Deformer& d, const RigPose& pose,
            std::vector<TriangleMesh>& meshes) {
  std::vector<Mat4> joints;
  if (d.skin >= 0) joints = joint_matrices(rig.skins[size_t(d.skin)], pose);
  const std::vector<double>& weights = pose.weights[size_t(d.node)];
  for (size_t i = 0; i < d.parts.size() && i < meshes.size(); ++i)
    deform_part(d.parts[i], weights, d.skin >= 0 ? &joints : nullptr, meshes[i].positions,
                meshes[i].normals);
}

}  // namespace anamorph
