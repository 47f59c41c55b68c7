// The six faces of a cubemap (the cubemap preset and the cubemap source projection share them).
// Face order: +X, -X, +Y, -Y, +Z, -Z of camera space (x right, y up, z back; -Z is the look_at
// direction). In face f at face position (s, t) in [0,1]^2 (t downward) the direction is
//   axis_f + (2s - 1) right_f + (2t - 1) down_f.
#pragma once

#include <array>
#include <optional>

#include "math/vec.h"

namespace anamorph {

struct CubeFace {
  Vec3 axis, right, down;
};

using CubeFaceTable = std::array<CubeFace, 6>;

namespace cube_axes {
constexpr Vec3 X{1, 0, 0}, Y{0, 1, 0}, Z{0, 0, 1};
}

// "inside": every face is the un-mirrored view from the cube's center (side faces upright; +Y
// seen looking up with -Z at its bottom edge, -Y looking down with -Z at its top edge).
// right = axis x up, down = -up.
inline constexpr CubeFaceTable kCubeInside = {{
    {cube_axes::X, cube_axes::Z, -cube_axes::Y},    // +X: up +y
    {-cube_axes::X, -cube_axes::Z, -cube_axes::Y},  // -X: up +y
    {cube_axes::Y, cube_axes::X, -cube_axes::Z},    // +Y: up +z (back), -Z at the bottom edge
    {-cube_axes::Y, cube_axes::X, cube_axes::Z},    // -Y: up -z (front), at the top edge
    {cube_axes::Z, -cube_axes::X, -cube_axes::Y},   // +Z: up +y
    {-cube_axes::Z, cube_axes::X, -cube_axes::Y},   // -Z: up +y
}};

// "opengl": OpenGL 4.6 table 8.19: s = (sc / |ma| + 1) / 2, t = (tc / |ma| + 1) / 2.
inline constexpr CubeFaceTable kCubeOpenGl = {{
    {cube_axes::X, -cube_axes::Z, -cube_axes::Y},   // +rx: sc = -rz, tc = -ry
    {-cube_axes::X, cube_axes::Z, -cube_axes::Y},   // -rx: sc = +rz, tc = -ry
    {cube_axes::Y, cube_axes::X, cube_axes::Z},     // +ry: sc = +rx, tc = +rz
    {-cube_axes::Y, cube_axes::X, -cube_axes::Z},   // -ry: sc = +rx, tc = -rz
    {cube_axes::Z, cube_axes::X, -cube_axes::Y},    // +rz: sc = +rx, tc = -ry
    {-cube_axes::Z, -cube_axes::X, -cube_axes::Y},  // -rz: sc = -rx, tc = -ry
}};

// The layout position of a direction `q` (any length): the face whose axis has the largest
// projection, in a cols x rows grid of faces (3x2 or 6x1; faces in order, row by row), u left to
// right and v top to bottom in [0,1]^2 (not clamped). None for a zero vector.
inline std::optional<Vec2> cube_layout_position(const CubeFaceTable& faces, int cols, int rows,
                                                const Vec3& q) {
  int best = -1;
  double best_dot = 0;
  for (int i = 0; i < 6; ++i) {
    const double d = dot(q, faces[size_t(i)].axis);
    if (d > best_dot) best_dot = d, best = i;
  }
  if (best < 0) return std::nullopt;
  const CubeFace& f = faces[size_t(best)];
  const double s = 0.5 * (dot(q, f.right) / best_dot + 1),
               t = 0.5 * (dot(q, f.down) / best_dot + 1);
  return Vec2{((best % cols) + s) / cols, ((best / cols) + t) / rows};
}

}  // namespace anamorph
