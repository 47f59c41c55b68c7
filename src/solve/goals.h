// The residuals of the camera's constraints (scene/camera_goals.h) for one camera: what the
// solver drives to zero and what the report shows. Pins, keep and straight are in pixels, size and
// magnification in percent of their target.
#pragma once

#include <functional>
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
// The same with dF/dk from the rays' own derivative with respect to the key at uv (`dorg`,
// `ddir`: VirtualCamera::key_derivative, exact).
bool image_position_derivative(const Camera& cam, const Vec3& p, Vec2 uv, const Vec3& dorg,
                               const Vec3& ddir, Vec2* duv_dk);
// How the image position `uv` of the world point `p` moves with a key: duv/dk (false: undecided).
using PositionDerivative = std::function<bool(const Vec3& p, Vec2 uv, Vec2* duv_dk)>;

class Goals {
 public:
  // Points named by objects are their bounding boxes' centres in `loaded`; keep's samples are
  // taken through `start`. Throws SceneError (an unknown or ambiguous object name).
  Goals(const CameraGoals& goals, const Scene& loaded, const Camera& start, int width, int height);

  size_t size() const { return items_.size(); }
  const CameraConstraint& constraint(size_t i) const { return items_[i].c; }
  int residual_count(size_t i) const;
  // Residuals of constraint i (residual_count of them, unweighted): residuals_at the image
  // positions of its points. Not `exact`: pins and keep find their points' image positions from
  // their targets (Camera::project_near), the solver's fast path; measure() uses the whole
  // inverse map.
  void residuals(size_t i, const CameraPair& cam, double* r, bool exact = false) const;
  // The reported size of constraint i's residual (pixels or percent; +inf when the camera does
  // not see its point) and its unit.
  double measure(size_t i, const CameraPair& cam) const;
  const char* unit(size_t i) const;
  // The world points whose image positions the residuals of constraint i are a function of: pin,
  // magnification: its point; size: from, to; keep: its samples; straight: its segment's.
  std::vector<Vec3> points(size_t i) const;
  // Where `cam` shows them (as residuals() finds them); (inf, inf) for a point not seen.
  std::vector<Vec2> positions(size_t i, const Camera& cam, bool exact = false) const;
  // The residuals at given image positions of points(i). They depend on the camera only through
  // its rays at those positions (generate), never its inverse map, and only for the kinds that
  // moves_at_fixed_positions (magnification: the ray differentials there); the others are
  // functions of the positions alone.
  void residuals_at(size_t i, const CameraPair& cam, const std::vector<Vec2>& uvs, double* r) const;
  bool moves_at_fixed_positions(size_t i) const;
  // dr/du and dr/dv of each point's position (rows 2 k, 2 k + 1, residual_count each) at the
  // positions `uv` through `cam`: central differences of residuals_at in uv (zero for a point not
  // seen; goals_jacobian.cpp).
  std::vector<std::vector<double>> by_positions(size_t i, const CameraPair& cam,
                                                const std::vector<Vec2>& uv) const;
  // dr/dk (residual_count values into `col`) by the chain rule: dr/duv (by_positions at `uv`, the
  // positions through `cam`) times duv/dk (`duv_dk`), plus for moves_at_fixed_positions
  // `at_fixed_positions` (dr/dk at the same uv). Never the inverse map. False when a position's
  // derivative is undecided.
  bool derivative(size_t i, const PositionDerivative& duv_dk, const std::vector<Vec2>& uv,
                  const std::vector<std::vector<double>>& dr_duv, double* col,
                  const double* at_fixed_positions = nullptr) const;
  // The same with duv/dk by image_position_derivative with `minus`, `plus` (the cameras with the
  // key at k - h1, k + h2, step = h1 + h2), and the fixed-position term the difference of
  // residuals_at through them.
  bool derivative(size_t i, const CameraPair& cam, const CameraPair& minus, const CameraPair& plus,
                  double step, const std::vector<Vec2>& uv,
                  const std::vector<std::vector<double>>& dr_duv, double* col) const;
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
  double magnification_residual(const Item& it, const CameraPair& cp, Vec2 uv) const;
  std::vector<Item> items_;
  int width_, height_;
};

}  // namespace anamorph::solve
