// Mesh file loaders: glTF 2.0 through tinygltf (.gltf, .glb, data URIs), everything else that
// assimp reads (OBJ/MTL, PLY, STL, ...) through assimp. Both produce the same LoadedModel.
//
// Conventions of a LoadedModel (the details of each format are at the top of gltf_loader.cpp
// and assimp_loader.cpp):
// - uvs have (0,0) at the image's top-left, v growing downwards (glTF's convention, and the
//   texture lookup's: image row 0 = top). glTF uvs are stored as given; assimp's (OpenGL,
//   v up) are stored as (u, 1 - v).
// - normals are unit length. Empty normals mean flat shading: glTF asks for that when a
//   primitive has none; assimp meshes without normals get smooth normals with a 60 degree
//   crease instead.
// - positions are finite, indices in range, zero-area triangles dropped.
// - materials holds only the materials the loaded meshes use (in first-use order); glTF files
//   give MetallicRoughness materials, assimp files Whitted ones.
#pragma once

#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "material/material.h"
#include "model/mesh.h"
#include "scene/gltf_rig.h"

namespace anamorph {

struct LoadError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A camera found in the file (glTF cameras), placed in the model's space.
struct ModelCamera {
  std::string name;
  bool perspective = true;
  double yfov = 0.8;            // radians (perspective)
  double aspect = 0;            // 0 = use the image's
  double xmag = 1, ymag = 1;    // half extents (orthographic)
  Transform world_from_camera;  // camera looks along -z, +y up (glTF convention)
};

// A light found in the file (glTF KHR_lights_punctual), in the file's photometric units,
// placed in the model's space. scene/gltf_lights.h converts it to a Light.
struct ModelLight {
  enum class Type { Point, Spot, Directional };
  std::string name;
  Type type = Type::Point;
  Color color{1, 1, 1};
  double intensity = 1;   // candela (point, spot) or lux (directional)
  double range = 0;       // 0: unlimited (point, spot)
  double inner_cone = 0;  // spot: radians from the axis
  double outer_cone = kPi / 4;
  Transform world_from_light;  // the light shines along -z
};

struct LoadedModel {
  MaterialList materials;             // indices used by meshes refer to this list
  std::vector<Prototype> prototypes;  // each mesh built once...
  std::vector<Instance> instances;    // ...and placed by nodes (model space)
  std::vector<ModelCamera> cameras;
  std::vector<ModelLight> lights;
  // glTF: the node hierarchy, animations, skins and deforming meshes (null for other formats).
  // The lists above hold the file's static pose (its nodes as written, no animation applied).
  std::shared_ptr<const GltfRig> rig;
  std::vector<std::string> warnings;  // repaired problems (zero normals, unknown extensions)
  // What the file held and what of it was read (glTF: counts, extensions), for `anamorph info`.
  std::vector<std::string> summary;

  size_t triangle_count() const {  // unique triangles (each prototype once)
    size_t n = 0;
    for (const auto& p : prototypes)
      for (const auto& m : p.meshes) n += m.triangle_count();
    return n;
  }
};

// Dispatches on the extension. Throws LoadError with a message naming the file on any failure:
// missing file, parse error, non-finite positions, out-of-range indices.
LoadedModel load_model(const std::filesystem::path& file);
LoadedModel load_gltf(const std::filesystem::path& file);
LoadedModel load_with_assimp(const std::filesystem::path& file);

}  // namespace anamorph
