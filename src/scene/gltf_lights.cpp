#include "scene/gltf_lights.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace anamorph {

namespace {

int light_index(const tinygltf::Node& node) {
  const auto it = node.extensions.find("KHR_lights_punctual");
  if (it == node.extensions.end() || !it->second.IsObject() || !it->second.Has("light")) return -1;
  const tinygltf::Value& v = it->second.Get("light");
  if (!v.IsNumber()) return -2;
  const double d = v.GetNumberAsDouble();
  return d >= 0 && d < 1e9 && d == std::floor(d) ? int(d) : -2;
}

}  // namespace

std::optional<ModelLight> read_node_light(const tinygltf::Model& m, const tinygltf::Node& node,
                                          const std::string& node_name, const Mat4& world,
                                          std::vector<std::string>& warnings) {
  const int index = light_index(node);
  if (index == -1) return std::nullopt;
  if (index < 0 || size_t(index) >= m.lights.size())
    throw LoadError(fmt::format(
        "node '{}': KHR_lights_punctual light {} does not exist ({} lights)", node_name,
        index == -2 ? std::string("(not an index)") : std::to_string(index), m.lights.size()));
  const tinygltf::Light& gl = m.lights[size_t(index)];
  ModelLight l;
  l.name = gl.name.empty() ? node_name : gl.name;
  if (gl.type == "point")
    l.type = ModelLight::Type::Point;
  else if (gl.type == "spot")
    l.type = ModelLight::Type::Spot;
  else if (gl.type == "directional")
    l.type = ModelLight::Type::Directional;
  else
    throw LoadError(
        fmt::format("light '{}': type '{}' is not point, spot or directional", l.name, gl.type));
  const auto warn = [&](const std::string& what) {
    warnings.push_back(fmt::format("light '{}': {}", l.name, what));
  };
  if (gl.color.size() == 3) {
    l.color = {gl.color[0], gl.color[1], gl.color[2]};
    if (!(min_component(l.color) >= 0) || !std::isfinite(max_component(l.color))) {
      warn("color out of range; white used");
      l.color = {1, 1, 1};
    }
  }
  l.intensity = gl.intensity;
  if (!(l.intensity >= 0) || !std::isfinite(l.intensity)) {
    warn(fmt::format("intensity {} is not >= 0; 0 used", l.intensity));
    l.intensity = 0;
  }
  l.range = gl.range > 0 && std::isfinite(gl.range) ? gl.range : 0;
  if (l.type == ModelLight::Type::Spot) {
    double outer = gl.spot.outerConeAngle, inner = gl.spot.innerConeAngle;
    if (!(outer > 0 && outer <= kPi / 2)) {
      warn(fmt::format("outerConeAngle {} is not in (0, pi/2]; clamped", outer));
      outer = std::clamp(std::isfinite(outer) ? outer : kPi / 4, 1e-6, kPi / 2);
    }
    if (!(inner >= 0 && inner < outer)) {
      warn(fmt::format("innerConeAngle {} is not in [0, outerConeAngle); clamped", inner));
      inner = std::clamp(std::isfinite(inner) ? inner : 0.0, 0.0, outer * (1 - 1e-9));
    }
    l.inner_cone = inner;
    l.outer_cone = outer;
  }
  l.world_from_light = Transform(world);
  return l;
}

void place_light(Light& light, const Transform& world_from_light) {
  light.position = world_from_light.point({0, 0, 0});
  const Vec3 d = world_from_light.vector({0, 0, -1});
  light.direction = length(d) > 0 && std::isfinite(length(d)) ? normalize(d) : Vec3{0, 0, -1};
}

Light scene_light(const ModelLight& l, const Transform& world_from_light, bool cycles_spots) {
  Light s;
  s.name = l.name;
  s.intensity = l.color * (l.intensity / kLumensPerWatt);
  s.range = l.range;
  place_light(s, world_from_light);
  switch (l.type) {
    case ModelLight::Type::Point:
      s.kind = Light::Kind::Point;
      break;
    case ModelLight::Type::Spot:
      s.kind = Light::Kind::Spot;
      s.cone_angle = degrees(l.inner_cone);
      s.cone_falloff = degrees(l.outer_cone - l.inner_cone);
      s.spot_falloff = cycles_spots ? Light::SpotFalloff::Cycles : Light::SpotFalloff::Gltf;
      break;
    case ModelLight::Type::Directional:
      s.kind = Light::Kind::Directional;
      s.range = 0;
      break;
  }
  return s;
}

}  // namespace anamorph
