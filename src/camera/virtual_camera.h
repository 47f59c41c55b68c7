// The virtual camera: org and dir functions composed with a rig transform and depth of field.
// Presets build one of these; the renderer sees only the Camera interface.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "camera/camera.h"
#include "camera/coins.h"
#include "camera/functions.h"
#include "camera/ray_kernels.h"
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

// A camera key the solver differentiates by (docs/solve.md): a preset key ("fov", "look_at") or,
// with coin >= 0, a key of that [[camera.coin]] ("strength", "radius", "stiffness", "position");
// `component` of a vector.
struct CameraKey {
  int coin = -1;
  std::string name;
  int component = 0;
};

// Derivatives a preset gives in closed form with respect to its own keys (the camera solver's).
struct PresetDerivatives {
  // G = rig^-1 d(rig)/d(key[component]) (look_from, look_at, up): a factor on the right, so that a
  // transform put before the rig (`transform`) leaves it valid. False: not a key of the rig.
  std::function<bool(std::string_view key, int component, Mat4* g)> rig;
  // d(org, dir)/d(key) of the camera-space ray `plain` at its (u, v) held fixed (before coins;
  // `plain` has a unit direction). False: not a key it differentiates.
  using RayFn =
      std::function<bool(std::string_view key, const CameraRay& plain, Vec3* dorg, Vec3* ddir)>;
  RayFn ray;
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
  PresetDerivatives derivatives;  // none: the solver differentiates by differences
};

struct DepthOfField {
  double aperture_radius = 0;  // 0 = pinhole: the exact undisplaced ray
  double focus_distance = 1;   // along each ray, from its origin
};

class VirtualCamera final : public Camera {
 public:
  VirtualCamera(VirtualCameraParts parts, DepthOfField dof = {});

  // A ray whose origin lies beyond kMaxCoordinate (math/input_limits.h) is no ray: the renderer
  // never hands one to Embree, which asserts on origins past 1.8e18.
  std::optional<CameraRay> generate(const CameraSample& s) const override;
  void generate_batch(const CameraSample* s, int n, CameraRayBatch* out) const override;
  bool uses_lens_or_time() const override { return dof_.aperture_radius > 0 || moving_; }
  // Under a rolling shutter with camera motion, each image position's ray is that of the rig at
  // its readout time (project_rolling).
  std::vector<Vec2> project(const Vec3& p) const override;
  // Where project searches (coins, no closed form): Gauss-Newton from `seed` alone, and the whole
  // search only when that does not converge.
  std::vector<Vec2> project_near(const Vec3& p, Vec2 seed) const override;
  std::string describe() const override { return description_; }

  // The ray before depth of field and in camera space (for tests and the inverse map).
  std::optional<CameraRay> generate_pinhole(Vec2 uv) const;
  // The same before the coins deform it (what they deform).
  std::optional<CameraRay> generate_uncoined(Vec2 uv) const;
  // d(org, dir)/d(key) of generate()'s ray at uv (world space), exact: forward-mode dual numbers
  // through the coins and the rig, with the coins' image positions moved by the implicit function
  // theorem (camera/key_derivative.cpp). False where not given: a key the preset does not
  // differentiate, a dropped coin's strength, lens, motion, a projective rig.
  bool key_derivative(const CameraKey& key, Vec2 uv, Vec3* dorg, Vec3* ddir) const;
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
  // The closed-form inverse under a moving rolling shutter: from the images with the rig at
  // open, the fixed point uv = inverse(rig at shutter_time(uv)) by iteration.
  std::vector<Vec2> project_rolling(const Vec3& p) const;
  // What the constructor finds out about the functions and the rig.
  void detect_linear_field();
  void detect_point_origin();
  // The kernels, chosen once (called again when the coins are built; see the .cpp for the table).
  void choose_kernels(bool rig_affine, bool rig_rotation);

  // Rays of n <= kCameraBatch samples of a camera with no lens or motion under an affine rig:
  // the packet kernels. generate() runs the camera's one with n = 1, so single rays and packets
  // agree bit for bit. An affine field's closed form, or the functions in batch and then the
  // finishing pass; with coins, the samples a coin reaches again in camera space, deformed, and
  // taken through the rig.
  template <bool kCoins>
  void affine_rays(const double* u, const double* v, int n, CameraRayBatch* out) const;
  template <bool kPointOrg, bool kCoins>
  void function_rays(const double* u, const double* v, int n, CameraRayBatch* out) const;
  // The lanes of `out` that coins reach, from `plain` (the same rays in camera space; deformed
  // in place).
  void deform_by_coins(const double* u, const double* v, int n, CameraRayBatch* plain,
                       CameraRayBatch* out) const;
  // generate() and generate_batch() before the world's bound is applied to the origins.
  std::optional<CameraRay> generate_any(const CameraSample& s) const;
  void generate_batch_any(const CameraSample* s, int n, CameraRayBatch* out) const;
  // One ray at a time: cameras with a lens, motion or a projective rig.
  std::optional<CameraRay> general_ray(const CameraSample& s) const;
  void to_world(CameraRay* r, const Transform& rig) const;  // and normalize again

  std::unique_ptr<OrgFunction> org_;
  std::unique_ptr<DirFunction> dir_;
  std::unique_ptr<InverseMap> inverse_;
  Transform world_from_camera_;
  bool rig_identity_;
  AffineRig rig34_{};  // the rig's upper 3x4, as the kernels apply it
  DepthOfField dof_;
  std::string description_;
  PresetDerivatives derivatives_;
  // An affine ray field (detect_linear_field), in world space and in camera space (rays under
  // coins).
  bool linear_ = false;
  AffineField world_field_, camera_field_;
  // A point origin (most presets): evaluated once, in every lane; null otherwise.
  std::unique_ptr<SurfaceBatch> point_batch_;
  CoinField coins_;
  std::vector<std::string> coin_warnings_;
  bool moving_ = false;
  RigidMotion motion_;
  Shutter shutter_;

  // The chosen kernels. packet_ null: one ray at a time (general_ray).
  using PacketKernel = void (VirtualCamera::*)(const double* u, const double* v, int n,
                                               CameraRayBatch* out) const;
  PacketKernel packet_ = nullptr;
  AffineKernel affine_ = nullptr;
  void (OrgFunction::*org_batch_)(const double*, const double*, int, SurfaceBatch*) const = nullptr;
  FinishKernel finish_world_ = nullptr, finish_camera_ = nullptr;
};

// Numeric inverse map for any camera: a coarse grid over [0,1]^2, then Gauss-Newton on the
// point-to-ray distance from each local minimum; distinct solutions within tolerance are kept.
std::vector<Vec2> project_numeric(const Camera& cam, const Vec3& p, int grid = 48);
// Gauss-Newton on the point-to-ray distance from `seed` alone: the image position it converges
// to, or none.
std::optional<Vec2> project_numeric_from(const Camera& cam, const Vec3& p, Vec2 seed);

}  // namespace anamorph
