// Everything a render needs, after parsing and loading, before acceleration structures.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "camera/camera.h"
#include "scene/light.h"
#include "scene/material.h"
#include "scene/mesh.h"
#include "scene/shape.h"

namespace anamorph {

struct RenderSettings {
  int width = 640, height = 480;
  std::string integrator = "whitted";  // whitted | path | albedo | normal | depth | position | id | uv
  int spp = 1;
  std::string sampler = "stratified";  // center | stratified | random
  int max_depth = 5;
  uint64_t seed = 0;
  std::string filter = "box";          // box | gaussian
  double filter_radius = 1.5;          // gaussian: radius in pixels (box: pixel area)
  double ray_epsilon = 1e-4;           // offset of secondary ray origins (relative to scale)
  int tile_size = 32;
};

struct Scene {
  std::string path;  // the scene file
  RenderSettings render;
  std::unique_ptr<Camera> camera;
  std::string camera_toml;  // the [camera] table as written (for metadata)

  std::vector<Material> materials;
  std::vector<Prototype> prototypes;
  std::vector<Instance> instances;
  std::vector<AnalyticShape> shapes;
  std::vector<Light> lights;
  Environment environment;
  std::vector<std::string> warnings;

  size_t triangle_count() const;  // unique (prototype) triangles
  size_t instanced_triangle_count() const;
};

}  // namespace anamorph
