// Textures: constant, image (mip-mapped, filtered by the ray footprint), and the procedural
// `checker` and `grid` patterns in object, world or uv space.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "io/image.h"
#include "math/transform.h"
#include "math/vec.h"

namespace anamorph {

enum class Wrap { Repeat, Clamp, Mirror };

// 2x3 affine transform of texture coordinates (KHR_texture_transform).
struct UvTransform {
  double m[2][3] = {{1, 0, 0}, {0, 1, 0}};
  Vec2 apply(Vec2 uv) const {
    return {m[0][0] * uv.x + m[0][1] * uv.y + m[0][2], m[1][0] * uv.x + m[1][1] * uv.y + m[1][2]};
  }
  Vec2 apply_vector(Vec2 d) const {
    return {m[0][0] * d.x + m[0][1] * d.y, m[1][0] * d.x + m[1][1] * d.y};
  }
  bool identity() const {
    return m[0][0] == 1 && m[0][1] == 0 && m[0][2] == 0 && m[1][0] == 0 && m[1][1] == 1 &&
           m[1][2] == 0;
  }
  static UvTransform from_offset_rotation_scale(Vec2 offset, double rotation, Vec2 scale);
};

// Everything a texture lookup may need about the shading point.
struct TexCoord {
  Vec2 uv;                 // surface parameterization
  Vec2 duvdx, duvdy;       // uv change across one pixel (ray differentials); zero = no filtering
  Vec3 p_world;            // hit point in world space
  Vec3 p_object;           // hit point in object space
  Vec3 dpdx, dpdy;         // world-space footprint of one pixel
  Vec3 n_world, n_object;  // geometric normal (procedural 3D patterns drop the axis along it)
  Transform const* object_from_world = nullptr;  // for object-space footprints (null = identity)
};

class MipMap;

struct Texture {
  enum class Kind { Constant, Image, Checker, Grid };
  enum class Space { Uv, Object, World };
  Kind kind = Kind::Constant;
  Color value{1, 1, 1};  // Constant
  // Image
  std::shared_ptr<const MipMap> image;
  Wrap wrap_s = Wrap::Repeat, wrap_t = Wrap::Repeat;
  bool nearest = false;
  UvTransform uv_transform;
  // Procedural
  Space space = Space::Uv;
  Color color_a{0.9, 0.9, 0.9}, color_b{0.1, 0.1, 0.1};
  double scale = 1;              // pattern period in the chosen space
  double line_width = 0.05;      // grid: fraction of the period
  Transform pattern_from_space;  // extra placement of the pattern

  // RGB and alpha at the shading point; filtered by the footprint where possible.
  Color eval(const TexCoord& tc, double* alpha = nullptr) const;
  static Texture constant(Color c) {
    Texture t;
    t.value = c;
    return t;
  }
};

// A box-filtered mip pyramid of a linear RGBA image; trilinear lookups.
class MipMap {
 public:
  explicit MipMap(Image base);
  // RGBA at uv with a filter width (in uv units, larger axis of the footprint).
  void lookup(Vec2 uv, double width, Wrap ws, Wrap wt, bool nearest, float out[4]) const;
  const Image& level(int i) const { return levels_[size_t(i)]; }
  int levels() const { return int(levels_.size()); }

 private:
  void bilinear(int level, Vec2 uv, Wrap ws, Wrap wt, float out[4]) const;
  std::vector<Image> levels_;
};

}  // namespace anamorph
