// Delta light sources. Area lights (quad and sphere lights in the scene file, emissive meshes and
// shapes) are emissive geometry; the renderer's light sampler collects them.
#pragma once

#include <memory>
#include <string>

#include "material/texture.h"
#include "math/transform.h"

namespace anamorph {

struct Light {
  enum class Kind { Point, Spot, Directional };
  Kind kind = Kind::Point;
  Color intensity{1, 1, 1};  // Point/Spot: W/sr (radiant intensity); Directional: irradiance
  Vec3 position{0, 0, 0};    // Point, Spot
  Vec3 direction{0, -1, 0};  // Spot, Directional (direction light travels)
  double cone_angle = 30;    // Spot: full-intensity half angle, degrees
  double cone_falloff = 5;   // Spot: smooth falloff width beyond cone_angle, degrees
  std::string name;
};

struct Environment {
  Color color{0, 0, 0};                // constant radiance (used when no image)
  std::shared_ptr<const Image> image;  // equirectangular, linear RGB
  double strength = 1;
  double rotation = 0;  // degrees about +y
  bool present() const { return image || max_component(color) > 0; }
};

}  // namespace anamorph
