// The virtual camera: org and dir functions composed with a rig transform and depth of field.
// Presets build one of these; the renderer sees only the Camera interface.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "camera/camera.h"
#include "camera/coins.h"
#include "camera/functions.h"
#include "math/rigid_motion.h"
#include "math/transform.h"

namespace anamorph {

// A closed-form inverse of a preset's org/dir: every (u, v) whose pinhole ray passes through a
// point given in camera space (before the rig). Valid only for the undeformed org/dir it was built
// with; without one, VirtualCamera::project falls back to project_numeric.
class InverseMap {
 public:
  virtual ~InverseMap() = default;
  virtual std::vector<Vec2> project(const Vec3& p_camera) const = 0;
};

// Camera motion over the shutter: the rig moves from `open` to `close` (times in [0,1] of the
// shutter interval, sampled per ray by CameraSample::time). A rolling shutter makes a ray's time
// a function of its image position instead: 0 where the readout starts, 1 where it ends, along
// `rolling_angle` (degrees from +u toward +v; 90 = top to bottom).
struct Shutter {
  bool rolling = false;
  double rolling_angle = 90;
};

struct VirtualCameraParts {
  std::unique_ptr<OrgFunction> org;
  std::unique_ptr<DirFunction> dir;
  Transform world_from_camera;  // the rig; identity when functions are given in world space
  std::string description;
  std::unique_ptr<InverseMap> inverse;  // optional closed-form inverse (see InverseMap)
  std::vector<Coin> coins;  // centers of interest (world space), applied between org/dir and rig
  // Motion blur: the rig at shutter close (world_from_camera is the rig at open); none = still.
  std::optional<Transform> world_from_camera_close;
  Shutter shutter;
};

struct DepthOfField {
  double aperture_radius = 0;  // 0 = pinhole: the exact undisplaced ray
  double focus_distance = 1;   // along each ray, from its origin
};

// The rig's upper 3x4 (an affine map), as the batch kernels apply it.
struct AffineRig {
  double m[3][4];
};

class VirtualCamera final : public Camera {
 public:
  VirtualCamera(VirtualCameraParts parts, DepthOfField dof = {});

  // A ray whose origin lies beyond kMaxCoordinate (math/input_limits.h) is no ray: the renderer
  // never hands one to Embree, which asserts on origins past 1.8e18.
  std::optional<CameraRay> generate(const CameraSample& s) const override;
  void generate_batch(const CameraSample* s, int n, CameraRayBatch* out) const override;
  bool uses_lens_or_time() const override { return dof_.aperture_radius > 0 || moving_; }
  std::vector<Vec2> project(const Vec3& p) const override;
  std::string describe() const override { return description_; }

  // The ray before depth of field and in camera space (for tests and the inverse map).
  std::optional<CameraRay> generate_pinhole(Vec2 uv) const;
  // True when org and dir are affine in (u, v) (perspective, orthographic, off-axis views): rays
  // then come from a closed form precomputed in world space instead of the function calls.
  // With coins, only samples that no coin reaches take it.
  bool has_linear_fast_path() const { return linear_; }

  // The coins with their image positions (for `info`, `--aov coins`), and what building them
  // found worth telling the user (coins not seen, overlapping strong coins).
  const CoinField& coins() const { return coins_; }
  const std::vector<std::string>& coin_warnings() const { return coin_warnings_; }

  // The rig (world_from_camera) at shutter open, and whether it moves while the shutter is open.
  const Transform& rig() const { return world_from_camera_; }
  bool moving() const { return moving_; }
  // The time in [0,1] of the shutter at which a sample's ray is taken.
  double shutter_time(const CameraSample& s) const;

 private:
  void detect_linear_field();
  void detect_point_origin();
  // The rays of n <= kCameraBatch samples with no lens, motion or coin: functions in batch, then
  // one vectorized pass for the rig, normalization and differentials. generate() runs the same
  // code with n = 1, so both give the same bits.
  // camera_space: without the rig (coins deform the field there).
  void plain_rays(const double* u, const double* v, int n, CameraRayBatch* out,
                  bool camera_space = false) const;
  // Rays of n <= kCameraBatch samples of a curved camera with coins (no lens or motion): the
  // functions once in batch; samples no coin reaches finish as plain_rays does, the others in
  // camera space, then per ray the coins and the rig. generate() runs it with n = 1, so single
  // rays and packets agree.
  void coin_rays(const double* u, const double* v, int n, CameraRayBatch* out) const;
  // An affine field's rays with coins: the closed form for all samples, and for the samples a
  // coin reaches the camera-space closed form deformed and taken through the rig (generate()
  // runs it with n = 1).
  void linear_coin_rays(const double* u, const double* v, int n, CameraRayBatch* out) const;
  // The lanes of `out` that coins reach, from `plain` (the same rays in camera space; deformed
  // in place).
  void deform_by_coins(const double* u, const double* v, int n, CameraRayBatch* plain,
                       CameraRayBatch* out) const;
  // The org and dir functions for a batch; returns the origin samples (`org` or, for a point
  // origin, the precomputed lanes).
  const SurfaceBatch& eval_functions(const double* u, const double* v, int n, SurfaceBatch* org,
                                     DirBatch* dir) const;
  // The rig (or none, camera_space), normalization and differentials for evaluated functions.
  void finish(const SurfaceBatch& org, const DirBatch& dir, bool camera_space, int n,
              CameraRayBatch* out) const;
  std::optional<CameraRay> generate_general(const CameraSample& s, bool camera_space = false) const;
  // generate() and generate_batch() before the world's bound is applied to the origins.
  std::optional<CameraRay> generate_any(const CameraSample& s) const;
  void generate_batch_any(const CameraSample* s, int n, CameraRayBatch* out) const;
  std::optional<CameraRay> linear_coin_ray(Vec2 uv) const;
  void to_world(CameraRay* r) const;  // the rig
  void to_world(CameraRay* r, const Transform& rig) const;

  std::unique_ptr<OrgFunction> org_;
  std::unique_ptr<DirFunction> dir_;
  std::unique_ptr<InverseMap> inverse_;
  Transform world_from_camera_;
  bool rig_identity_;
  bool rig_affine_;                 // no projective row: plain_rays applies it as 3x4
  bool rig_rotation_ = false;       // its 3x3 part is orthonormal (keeps lengths)
  bool unit_dirs_ = false;          // dir_->unit_length(): the finish need not normalize
  bool org_first_order_ = false;    // dir_ reads only p, dpdu, dpdv of its origin samples
  AffineRig rig34_{}, camera34_{};  // that 3x4, and the identity (camera space)
  bool point_org_ = false;  // org is one point (most presets): evaluated once, in every lane
  std::unique_ptr<SurfaceBatch> point_batch_;
  DepthOfField dof_;
  std::string description_;
  // Affine ray field in world space: org = o0 + u o_u + v o_v, raw dir = d0 + u d_u + v d_v.
  bool linear_ = false;
  Vec3 o0_, o_u_, o_v_, d0_, d_u_, d_v_;
  Vec3 co0_, co_u_, co_v_, cd0_, cd_u_, cd_v_;  // the same in camera space (rays under coins)
  CoinField coins_;
  std::vector<std::string> coin_warnings_;
  bool moving_ = false;
  RigidMotion motion_;
  Shutter shutter_;
};

// Numeric inverse map for any camera: a coarse grid over [0,1]^2, then Gauss-Newton on the
// point-to-ray distance from each local minimum; distinct solutions within tolerance are kept.
std::vector<Vec2> project_numeric(const Camera& cam, const Vec3& p, int grid = 48);

}  // namespace anamorph
