// The derivatives of the constraints' residuals with respect to a camera key by the chain rule
// through the image positions of their points (docs/solve.md "How it solves").
#include <cmath>

#include "solve/goals.h"

namespace anamorph::solve {

std::vector<std::vector<double>> Goals::by_positions(size_t i, const CameraPair& cam,
                                                     const std::vector<Vec2>& uv) const {
  const size_t m = size_t(residual_count(i));
  std::vector<std::vector<double>> d(2 * uv.size(), std::vector<double>(m, 0.0));
  std::vector<Vec2> q = uv;
  std::vector<double> plus(m), minus(m);
  constexpr double e = 1e-7;  // of the image: 1e-4 px at 1000 px
  for (size_t k = 0; k < uv.size(); ++k) {
    if (!std::isfinite(uv[k].x)) continue;
    for (int a = 0; a < 2; ++a) {
      double& c = a == 0 ? q[k].x : q[k].y;
      const double c0 = c;
      c = c0 + e;
      residuals_at(i, cam, q, plus.data());
      c = c0 - e;
      residuals_at(i, cam, q, minus.data());
      c = c0;
      for (size_t j = 0; j < m; ++j) d[2 * k + size_t(a)][j] = (plus[j] - minus[j]) / (2 * e);
    }
  }
  return d;
}

bool Goals::derivative(size_t i, const PositionDerivative& duv_dk, const std::vector<Vec2>& uv,
                       const std::vector<std::vector<double>>& dr_duv, double* col,
                       const double* at_fixed_positions) const {
  const size_t m = size_t(residual_count(i));
  const std::vector<Vec3> p = points(i);
  for (size_t j = 0; j < m; ++j) col[j] = at_fixed_positions ? at_fixed_positions[j] : 0;
  for (size_t k = 0; k < uv.size(); ++k) {
    if (!std::isfinite(uv[k].x)) continue;  // unseen: a constant penalty
    Vec2 d;
    if (!duv_dk(p[k], uv[k], &d)) return false;
    for (size_t j = 0; j < m; ++j) col[j] += dr_duv[2 * k][j] * d.x + dr_duv[2 * k + 1][j] * d.y;
  }
  return true;
}

bool Goals::derivative(size_t i, const CameraPair& cam, const CameraPair& minus,
                       const CameraPair& plus, double step, const std::vector<Vec2>& uv,
                       const std::vector<std::vector<double>>& dr_duv, double* col) const {
  const size_t m = size_t(residual_count(i));
  std::vector<double> fixed(m, 0.0);
  if (moves_at_fixed_positions(i) && step > 0) {
    std::vector<double> lo(m), hi(m);
    residuals_at(i, minus, uv, lo.data());
    residuals_at(i, plus, uv, hi.data());
    for (size_t j = 0; j < m; ++j) fixed[j] = (hi[j] - lo[j]) / step;
  }
  const PositionDerivative by_cameras = [&](const Vec3& p, Vec2 at, Vec2* d) {
    return image_position_derivative(*cam.camera, *minus.camera, *plus.camera, step, p, at, d);
  };
  return derivative(i, by_cameras, uv, dr_duv, col, fixed.data());
}

}  // namespace anamorph::solve
