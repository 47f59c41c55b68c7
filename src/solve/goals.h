// The residuals of the camera's constraints (scene/camera_goals.h) for one camera: what the
// solver drives to zero and what the report shows. Pins, keep and straight are in pixels, size and
// magnification in percent of their target.
#pragma once

#include <string>
#include <vector>

#include "camera/camera.h"
#include "math/vec.h"
#include "scene/camera_goals.h"
#include "scene/scene.h"

namespace anamorph::solve {

// A camera as the solver sees it: the camera and, for magnification, the same camera without its
// coins (null when no constraint needs it).
struct CameraPair {
  const Camera* camera = nullptr;
  const Camera* plain = nullptr;
};

// How the image position `uv` of the world point `p` (where `cam` shows it) moves with a camera
// key k, by the implicit function theorem: p stays on the ray at uv, F(uv, k) = (p - org) x dir =
// 0, so dF/duv duv/dk = -dF/dk, solved in least squares (F has 3 components of rank 2). dF/duv is
// analytic: the camera's ray differentials at uv. dF/dk is the difference of the rays at the same
// uv through `minus` and `plus` (the camera with the key at k - h1 and k + h2) over `step` (h1 +
// h2). False when a camera has no ray at uv or the rays do not decide duv (dF/duv singular).
bool image_position_derivative(const Camera& cam, const Camera& minus, const Camera& plus,
                               double step, const Vec3& p, Vec2 uv, Vec2* duv_dk);

class Goals {
 public:
  // Points named by objects are their bounding boxes' centres in `loaded`; keep's samples are
  // taken through `start`. Throws SceneError (an unknown or ambiguous object name).
  Goals(const CameraGoals& goals, const Scene& loaded, const Camera& start, int width, int height);

  size_t size() const { return items_.size(); }
  const CameraConstraint& constraint(size_t i) const { return items_[i].c; }
  int residual_count(size_t i) const;
  // Residuals of constraint i (residual_count of them, unweighted). Not `exact`: pins and keep
  // find their points' image positions from their targets (Camera::project_near), the solver's
  // fast path; measure() uses the whole inverse map.
  void residuals(size_t i, const CameraPair& cam, double* r, bool exact = false) const;
  // The reported size of constraint i's residual (pixels or percent; +inf when the camera does
  // not see its point) and its unit.
  double measure(size_t i, const CameraPair& cam) const;
  const char* unit(size_t i) const;
  // Pins and keep: the world points whose image positions are the residuals (pixels from
  // `targets`, u then v, in order); empty for the other kinds.
  struct PointGoal {
    std::vector<Vec3> points;
    std::vector<Vec2> targets;
  };
  PointGoal point_goal(size_t i) const;
  int width() const { return width_; }
  int height() const { return height_; }
  bool needs_plain() const;

 private:
  struct Item {
    CameraConstraint c;
    Vec3 point, to;             // pin, magnification: point; size: from, to
    Vec2 uv;                    // pin: target
    std::vector<Vec3> samples;  // keep: points seen by the starting camera; straight: the segment's
    std::vector<Vec2> at;       // keep: where it saw them
  };
  void straight_residuals(const Item& it, const Camera& cam, double* r) const;
  std::vector<Item> items_;
  int width_, height_;
};

}  // namespace anamorph::solve
