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
  // How a spot's intensity falls from its axis to the cone's edge, t going linearly in the
  // cosine of the angle to the axis from 0 at the outer angle to 1 at the inner one.
  // Smoothstep: 3t^2 - 2t^3 (the scene file's spot). Gltf: t^2 (KHR_lights_punctual's
  // recommended falloff). Cycles:
  // Blender 3.4 Cycles' spot: cos(angle to the axis) x smoothstep over a band of
  // (1 - cos outer) x blend in the cosine, blend = 1 - inner / outer (gltf_lights.h).
  enum class SpotFalloff { Smoothstep, Gltf, Cycles };
  Kind kind = Kind::Point;
  Color intensity{1, 1, 1};  // Point/Spot: W/sr (radiant intensity); Directional: irradiance
  Vec3 position{0, 0, 0};    // Point, Spot
  Vec3 direction{0, -1, 0};  // Spot, Directional (direction light travels)
  double cone_angle = 30;    // Spot: full-intensity half angle, degrees
  double cone_falloff = 5;   // Spot: smooth falloff width beyond cone_angle, degrees
  SpotFalloff spot_falloff = SpotFalloff::Smoothstep;
  // Point/Spot: beyond this distance no light (0: unlimited), with KHR_lights_punctual's
  // recommended window clamp(1 - (d / range)^4, 0, 1)^2 on the inverse square.
  double range = 0;
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
