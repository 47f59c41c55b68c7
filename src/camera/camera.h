// The camera contract from the paper: the raster image is a parameter space (u, v) in [0,1]^2,
// u left to right, v top to bottom. A camera maps a sample position to a ray origin org(u,v), a
// unit direction dir(u,v) and their derivatives (ray differentials), or to *no ray*.
// The renderer only ever sees this interface.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "math/vec.h"

namespace anamorph {

struct CameraSample {
  Vec2 uv;              // image position in [0,1]^2
  Vec2 lens{0.5, 0.5};  // lens sample in [0,1)^2 for depth of field
  double time = 0;      // shutter time in [0,1]
};

struct CameraRay {
  Vec3 org;
  Vec3 dir;  // unit length
  // Differentials: derivatives of origin and unit direction with respect to u and v (per unit of
  // parameter space, so multiply by 1/width, 1/height for one pixel's footprint).
  Vec3 dorg_du, dorg_dv;
  Vec3 ddir_du, ddir_dv;
};

// Up to kCameraBatch rays in structure-of-arrays form: what cameras compute vectorized and what
// the renderer's 4x4 primary packets consume (no transposition into CameraRay per lane).
inline constexpr int kCameraBatch = 16;
struct CameraRayBatch {
  static constexpr int N = kCameraBatch;
  double org[3][N], dir[3][N];
  double dorg_du[3][N], dorg_dv[3][N], ddir_du[3][N], ddir_dv[3][N];
  bool valid[N];

  static Vec3 at(const double (&a)[3][N], int i) { return {a[0][i], a[1][i], a[2][i]}; }
  Vec3 origin(int i) const { return at(org, i); }
  Vec3 direction(int i) const { return at(dir, i); }
  CameraRay ray(int i) const {
    return {at(org, i), at(dir, i), at(dorg_du, i), at(dorg_dv, i), at(ddir_du, i), at(ddir_dv, i)};
  }
  void set(int i, const std::optional<CameraRay>& r) {
    valid[i] = bool(r);
    const CameraRay c = r ? *r : CameraRay{};
    const auto put = [i](double(&a)[3][N], const Vec3& x) {
      a[0][i] = x.x, a[1][i] = x.y, a[2][i] = x.z;
    };
    put(org, c.org), put(dir, c.dir), put(dorg_du, c.dorg_du), put(dorg_dv, c.dorg_dv);
    put(ddir_du, c.ddir_du), put(ddir_dv, c.ddir_dv);
  }
};

// The positions of n <= kCameraBatch samples as two arrays u[i] = s[i].uv.x, v[i] = s[i].uv.y,
// for batch kernels.
void split_sample_positions(const CameraSample* s, int n, double* u, double* v);

class Camera {
 public:
  virtual ~Camera() = default;
  // Must be const, thread-safe and allocation-free.
  virtual std::optional<CameraRay> generate(const CameraSample& s) const = 0;
  // n <= kCameraBatch samples at once (the renderer's primary-ray packets): the same rays as
  // generate(), bit for bit, which cameras may compute faster together. `out->valid[i]` false
  // means no ray (the lane's other values are then unspecified).
  virtual void generate_batch(const CameraSample* s, int n, CameraRayBatch* out) const {
    for (int i = 0; i < n; ++i) out->set(i, generate(s[i]));
  }
  // Whether rays depend on CameraSample::lens or ::time (depth of field, motion); the renderer
  // draws those random numbers only when they matter.
  virtual bool uses_lens_or_time() const { return true; }
  // The inverse map: every (u, v) whose ray passes through `p` (may be empty or several).
  virtual std::vector<Vec2> project(const Vec3& p) const = 0;
  // The inverse map near `seed`: the image positions of `p` among which the one nearest `seed`
  // is found (a camera whose inverse is a search may return only the one it reaches from `seed`,
  // cheaper than project's search of the whole image). The camera solver's pins use it.
  virtual std::vector<Vec2> project_near(const Vec3& p, Vec2 seed) const {
    (void)seed;
    return project(p);
  }
  // Human-readable one-line description for `anamorph info` and file metadata.
  virtual std::string describe() const = 0;
};

}  // namespace anamorph
