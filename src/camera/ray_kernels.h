// The kernels VirtualCamera makes its packets of rays with (internal to the camera). Every packet
// goes through one loop, ray_lanes (ray_kernels.cpp), instantiated for the combinations cameras
// use; VirtualCamera picks its kernels once, at construction, with the instruction set
// (math/simd.h). The loop's compile-time choices:
//   - the source of the raw field: an affine closed form (AffineField), or the batches the origin
//     and direction functions wrote, with a point origin's one sample in every lane or a surface;
//   - the rig: none (camera space, or functions given in world space) or an affine 3x4;
//   - the directions: normalized, or already unit under a rig that keeps lengths.
#pragma once

#include "camera/functions.h"
#include "math/vec.h"

namespace anamorph {

// An affine ray field: org = o0 + u o_u + v o_v, raw dir = d0 + u d_u + v d_v (perspective,
// orthographic, off-axis views; VirtualCamera probes for it).
struct AffineField {
  Vec3 o0, o_u, o_v, d0, d_u, d_v;
  // The one formula of the field, per coordinate: a0 + u au + v av.
  [[gnu::always_inline]] static double at(double a0, double au, double av, double u, double v) {
    return a0 + au * u + av * v;
  }
  // The field at (u, v) as an origin sample and a raw direction (the general path).
  void sample(Vec2 uv, SurfaceSample* s, DirSample* d) const;
};

// The rig's upper 3x4 (an affine map), as the kernels apply it.
struct AffineRig {
  double m[3][4];
};

// The unit direction n = d / |d| and its derivatives d(d/|d|) = (dd - n (n . dd)) / |d|, in
// place: the one normalization of every camera ray. The kernels multiply by 1/|d| (one division
// for nine values); kDivide divides by |d| instead, as the general path (one ray at a time: lens,
// motion, coins' rig) always has. The two round differently, and each path keeps its bits.
template <bool kDivide>
[[gnu::always_inline]] inline void unit_direction(double len, double& x, double& y, double& z,
                                                  double& ux, double& uy, double& uz, double& vx,
                                                  double& vy, double& vz) {
  double inv = 0;
  if constexpr (!kDivide) inv = 1 / len;
  const auto by_len = [&](double a) __attribute__((always_inline)) {
    if constexpr (kDivide)
      return a / len;
    else
      return a * inv;
  };
  x = by_len(x), y = by_len(y), z = by_len(z);
  const double pu = x * ux + y * uy + z * uz, pv = x * vx + y * vy + z * vz;
  ux = by_len(ux - x * pu), uy = by_len(uy - y * pu), uz = by_len(uz - z * pu);
  vx = by_len(vx - x * pv), vy = by_len(vy - y * pv), vz = by_len(vz - z * pv);
}

// Rays of an affine field for n <= kCameraBatch positions (no rig: the field is given where the
// rays are wanted).
using AffineKernel = void (*)(const AffineField& f, const double* u, const double* v, int n,
                              CameraRayBatch* out);
// The rig, normalization and differentials for n origin samples and raw directions.
using FinishKernel = void (*)(const AffineRig& rig, const SurfaceBatch& org, const DirBatch& dir,
                              int n, CameraRayBatch* out);

// The finishing pass for one combination: a point origin (its one sample in lane 0 stands for
// all), no rig, unit directions (only rotated).
struct FinishKind {
  bool point_org, identity_rig, unit_dirs;
};

// The active instruction set's clones (math/simd.h).
AffineKernel affine_kernel();
FinishKernel finish_kernel(FinishKind kind);

}  // namespace anamorph
