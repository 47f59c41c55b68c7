// Object motion blur in the acceleration structure: where a ray's time falls among a geometry's
// time steps, and the pose there interpolated as Embree interpolates it (linearly between the two
// steps around it), so that the hit records of accel.cpp describe the surface Embree hit.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "math/transform.h"
#include "math/vec.h"

namespace anamorph::accel_detail {

// Time `time` in [0, 1] over `steps` >= 2 evenly spaced steps: segment i (steps i and i + 1) and
// the fraction f within it. (As Embree: the segment from the time scaled in float.)
struct TimeSegment {
  int i = 0;
  double f = 0;
};
inline TimeSegment time_segment(double time, size_t steps) {
  const float segments = float(steps - 1), ftime = float(time) * segments;
  const int i = std::clamp(int(std::floor(ftime)), 0, int(steps) - 2);
  return {i, double(ftime - float(i))};
}

inline Vec3 lerp_vertex(const std::vector<std::vector<Vec3f>>& steps, uint32_t v, TimeSegment s) {
  const Vec3 a(steps[size_t(s.i)][v]), b(steps[size_t(s.i) + 1][v]);
  return a * (1 - s.f) + b * s.f;
}

// The transform at `time`, its matrix interpolated entry by entry between the steps.
inline Transform transform_at(const std::vector<Transform>& steps, double time) {
  const TimeSegment s = time_segment(time, steps.size());
  const auto& a = steps[size_t(s.i)].matrix().m;
  const auto& b = steps[size_t(s.i) + 1].matrix().m;
  Mat4 m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m.m[r][c] = a[r][c] * (1 - s.f) + b[r][c] * s.f;
  return Transform(m);
}

}  // namespace anamorph::accel_detail
