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

class Camera {
 public:
  virtual ~Camera() = default;
  // Must be const, thread-safe and allocation-free.
  virtual std::optional<CameraRay> generate(const CameraSample& s) const = 0;
  // Many samples at once (the renderer's primary-ray packets); `valid[i]` false means no ray.
  // The same rays as generate(), which cameras may compute faster together.
  virtual void generate_batch(const CameraSample* s, int n, CameraRay* out, bool* valid) const {
    for (int i = 0; i < n; ++i) {
      const auto r = generate(s[i]);
      valid[i] = bool(r);
      if (r) out[i] = *r;
    }
  }
  // Whether rays depend on CameraSample::lens or ::time (depth of field, motion); the renderer
  // draws those random numbers only when they matter.
  virtual bool uses_lens_or_time() const { return true; }
  // The inverse map: every (u, v) whose ray passes through `p` (may be empty or several).
  virtual std::vector<Vec2> project(const Vec3& p) const = 0;
  // Human-readable one-line description for `anamorph info` and file metadata.
  virtual std::string describe() const = 0;
};

}  // namespace anamorph
