// The bounds anamorph puts on what it reads, each declared once: how far from the origin scene
// data may reach, and how deep any recursive input may nest. docs/scene-format.md
// ("Coordinates") and docs/robustness.md say why these numbers.
#pragma once

#include <cmath>

#include "math/vec.h"

namespace anamorph {

// The largest |coordinate| of anything in the world: object placements (after every transform
// is composed), shape sizes, mesh vertices, lights, camera positions, every ray's origin.
//
// Embree traverses in float and asserts (aborting the process) once a ray's origin or direction
// passes 1.844e18 (FLT_LARGE, `RayK::valid()`). Its triangle tests form products of three
// coordinate differences in float: with every coordinate within 1e12 those stay below
// (2e12)^3 = 8e36, inside float's 3.4e38, so nothing overflows to infinity on the way. Instances
// transform rays into their own space: accel/ flattens an instance whose inverse would carry a
// ray beyond FLT_LARGE. 1e12 scene units are 1e9 km in metres: the solar system with room.
inline constexpr double kMaxCoordinate = 1e12;

// Whether every component of `p` is finite and within kMaxCoordinate.
inline bool within_world(const Vec3& p) {
  return std::abs(p.x) <= kMaxCoordinate && std::abs(p.y) <= kMaxCoordinate &&
         std::abs(p.z) <= kMaxCoordinate;  // (false for NaN)
}

// A ray Embree may take: an origin within the world and a direction that is finite, not zero
// and no longer than the world is wide (a shadow ray's direction spans from a point to a light).
inline bool ray_in_range(const Vec3& o, const Vec3& d) {
  constexpr double kMaxDirection = 4 * kMaxCoordinate;
  return within_world(o) && std::abs(d.x) <= kMaxDirection && std::abs(d.y) <= kMaxDirection &&
         std::abs(d.z) <= kMaxDirection && (d.x != 0 || d.y != 0 || d.z != 0);
}

// ray_in_range for a ray already in float (a packet handed to Embree), as 0 or 1 from float
// comparisons alone, which a loop over a packet's lanes vectorizes. The same answer for every
// float ray: both limits round down to floats, so |x| <= limit in double iff |x| <= float(limit).
inline int ray_in_range_f(float ox, float oy, float oz, float dx, float dy, float dz) {
  constexpr float kWorld = float(kMaxCoordinate), kDir = float(4 * kMaxCoordinate);
  static_assert(double(kWorld) <= kMaxCoordinate && double(kDir) <= 4 * kMaxCoordinate);
  return int(std::abs(ox) <= kWorld) & int(std::abs(oy) <= kWorld) & int(std::abs(oz) <= kWorld) &
         int(std::abs(dx) <= kDir) & int(std::abs(dy) <= kDir) & int(std::abs(dz) <= kDir) &
         (int(dx != 0) | int(dy != 0) | int(dz != 0));
}

// How deep any recursive input may nest: TOML tables, arrays and dotted keys (a key of 50,000
// parts made toml++ recurse until the stack ran out), JSON in the editor's requests and in glTF
// files, `--set` key paths. A scene needs about 8 (camera.org.points: a table in a table, rows
// of [x, y, z]).
inline constexpr int kMaxNesting = 64;

}  // namespace anamorph
