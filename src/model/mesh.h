// Triangle meshes as loaded from files, before they become Embree geometry: plain data below
// camera/ (the mesh origin function reads them) and scene/ (whose loaders make them).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "math/transform.h"
#include "math/vec.h"

namespace anamorph {

// One triangle mesh with one material (a glTF primitive, an OBJ material group), object space.
struct TriangleMesh {
  std::string name;
  std::vector<Vec3f> positions;
  std::vector<Vec3f> normals;     // empty, or one per position (unit)
  std::vector<Vec2f> uvs;         // empty, or one per position
  std::vector<uint32_t> indices;  // 3 per triangle
  uint32_t material = 0;          // index into Scene::materials
  // Object motion blur of a deforming mesh: the positions (and normals, when it has them) at
  // evenly spaced times over the shutter, first at open, last at close (scene/scene_pose.h);
  // empty when it does not deform while the shutter is open.
  std::vector<std::vector<Vec3f>> motion_positions, motion_normals;
  size_t triangle_count() const { return indices.size() / 3; }
};

// A group of meshes built once and instanced many times (a glTF mesh, a whole OBJ file).
struct Prototype {
  std::string name;
  std::vector<TriangleMesh> meshes;
};

struct Instance {
  uint32_t prototype = 0;
  Transform world_from_object;
  std::string name;
  // Object motion blur: world_from_object at evenly spaced times over the shutter, first at open,
  // last at close (scene/scene_pose.h); empty when it does not move while the shutter is open.
  std::vector<Transform> motion;
};

}  // namespace anamorph
