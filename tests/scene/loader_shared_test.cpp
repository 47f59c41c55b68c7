// Loaders on the real third-party models in ../shared/scenes (see its MANIFEST.md for the
// counts checked here). Skipped with a message when ../shared is not beside the repository.
#include <algorithm>
#include <set>

#include <gtest/gtest.h>

#include "loader_fixture.h"
#include "material/metallic_roughness.h"
#include "material/whitted.h"
#include "material_util.h"
#include "scene/loaders.h"
#include "test_util.h"

namespace anamorph {
namespace {

using test::str;

std::filesystem::path scene(const std::string& rel) { return test::shared_scenes() / rel; }

// Bounds of every placed triangle vertex, in model space.
Bounds3 placed_bounds(const LoadedModel& m) {
  Bounds3 b;
  for (const Instance& in : m.instances)
    for (const TriangleMesh& tm : m.prototypes.at(in.prototype).meshes)
      for (const Vec3f& p : tm.positions) b.extend(in.world_from_object.point(Vec3(p)));
  return b;
}

void expect_unit_normals(const LoadedModel& m) {
  for (const Prototype& p : m.prototypes)
    for (const TriangleMesh& tm : p.meshes)
      for (size_t i = 0; i < tm.normals.size(); ++i)
        ASSERT_NEAR(length(Vec3(tm.normals[i])), 1.0, 1e-5) << tm.name << " normal " << i;
}

TEST(SharedModels, BoxTexturedIsTheSameInAllThreeContainers) {
  ANAMORPH_REQUIRE_SHARED();
  const LoadedModel a = load_model(scene("gltf/BoxTextured-glTF/BoxTextured.gltf"));
  const LoadedModel b = load_model(scene("gltf/BoxTextured-glTF-Binary/BoxTextured.glb"));
  const LoadedModel c = load_model(scene("gltf/BoxTextured-glTF-Embedded/BoxTextured.gltf"));
  for (const LoadedModel* m : {&a, &b, &c}) {
    ASSERT_EQ(m->prototypes.size(), 1u);
    ASSERT_EQ(m->prototypes[0].meshes.size(), 1u);
    EXPECT_EQ(m->triangle_count(), 12u);
    ASSERT_EQ(m->materials.size(), 1u);
    ASSERT_EQ(m->materials[0]->base_color.kind, Texture::Kind::Image);
  }
  const TriangleMesh& ma = a.prototypes[0].meshes[0];
  for (const LoadedModel* m : {&b, &c}) {
    const TriangleMesh& mo = m->prototypes[0].meshes[0];
    EXPECT_EQ(mo.positions, ma.positions);
    EXPECT_EQ(mo.indices, ma.indices);
    EXPECT_EQ(mo.uvs, ma.uvs);
    EXPECT_EQ(mo.normals, ma.normals);
    // .gltf + .bin reads CesiumLogoFlat.png with read_image; the others decode the embedded PNG
    // in tinygltf: both must give the same linear pixels.
    const Image& ia = a.materials[0]->base_color.image->level(0);
    const Image& io = m->materials[0]->base_color.image->level(0);
    ASSERT_EQ(io.width, ia.width);
    ASSERT_EQ(io.height, ia.height);
    ASSERT_EQ(io.pixels.size(), ia.pixels.size());
    size_t differ = 0;
    float worst = 0;
    for (size_t i = 0; i < ia.pixels.size(); ++i) {
      const float d = std::abs(io.pixels[i] - ia.pixels[i]);
      worst = std::max(worst, d);
      if (d > 1e-5f) ++differ;
    }
    EXPECT_EQ(differ, 0u) << "largest difference " << worst;
  }
  // The sampler of this older revision: wrapS MIRRORED_REPEAT, wrapT CLAMP_TO_EDGE.
  EXPECT_EQ(a.materials[0]->base_color.wrap_s, Wrap::Mirror);
  EXPECT_EQ(a.materials[0]->base_color.wrap_t, Wrap::Clamp);
  EXPECT_DOUBLE_EQ(test::material_as<MetallicRoughnessMaterial>(*a.materials[0]).metallic, 0);
  EXPECT_EQ(ma.uvs.size(), ma.positions.size());
}

TEST(SharedModels, BoxEmbeddedWithStrayByteStrideZero) {
  ANAMORPH_REQUIRE_SHARED();
  const LoadedModel m = load_model(scene("gltf/Box-glTF-Embedded/Box.gltf"));
  EXPECT_EQ(m.triangle_count(), 12u);
  expect_unit_normals(m);
  const Bounds3 b = placed_bounds(m);
  EXPECT_NEAR(length(b.diagonal()), std::sqrt(3.0), 1e-5) << str(b.lo) << " " << str(b.hi);
}

TEST(SharedModels, CamerasWithoutTopLevelScene) {
  ANAMORPH_REQUIRE_SHARED();
  const LoadedModel m = load_model(scene("gltf/Cameras/Cameras.gltf"));
  ASSERT_EQ(m.cameras.size(), 2u);
  const auto persp = std::count_if(m.cameras.begin(), m.cameras.end(),
                                   [](const ModelCamera& c) { return c.perspective; });
  EXPECT_EQ(persp, 1);
  for (const ModelCamera& c : m.cameras) {
    const Vec3 o = c.world_from_camera.point({0, 0, 0});
    EXPECT_NEAR(length(o - Vec3{0.5, 0.5, 3}), 0, 1e-12) << c.name << " at " << str(o);
    if (c.perspective) {
      EXPECT_DOUBLE_EQ(c.yfov, 0.7);
      EXPECT_DOUBLE_EQ(c.aspect, 1.0);
    } else {
      EXPECT_DOUBLE_EQ(c.xmag, 1.0);
      EXPECT_DOUBLE_EQ(c.ymag, 1.0);
    }
  }
  EXPECT_EQ(m.triangle_count(), 2u);
}

// KHR_materials_clearcoat read: factors, the coat's weight, roughness and normal textures.
TEST(SharedModels, ClearCoatTestReadsItsCoats) {
  ANAMORPH_REQUIRE_SHARED();
  const LoadedModel m = load_model(scene("gltf/ClearCoatTest-glTF/ClearCoatTest.gltf"));
  EXPECT_EQ(m.triangle_count(), 37116u);
  EXPECT_EQ(m.materials.size(), 19u);
  EXPECT_FALSE(test::has_warning(m, "KHR_materials_clearcoat")) << test::all_warnings(m);
  expect_unit_normals(m);
  const auto coat = [&](const std::string& name) -> const MetallicRoughnessMaterial& {
    for (const auto& mat : m.materials)
      if (mat->name == name) return test::material_as<MetallicRoughnessMaterial>(*mat);
    throw std::runtime_error("no material " + name);
  };
  EXPECT_EQ(coat("Simple_Coated").clearcoat, 1);
  EXPECT_NEAR(coat("Simple_Coated").clearcoat_roughness, 0.03, 1e-7);
  EXPECT_EQ(coat("Simple_Base").clearcoat, 0);
  EXPECT_EQ(coat("Partial_Coated").clearcoat_texture.kind, Texture::Kind::Image);
  EXPECT_EQ(coat("RoughVariations_Coated").clearcoat_roughness_texture.kind, Texture::Kind::Image);
  EXPECT_TRUE(coat("CoatNorm_Coated").has_clearcoat_normal);
  EXPECT_FALSE(coat("BaseNorm_Coated").has_clearcoat_normal);
  EXPECT_TRUE(coat("BaseNorm_Coated").has_normal_map);
}

TEST(SharedModels, AnimatedMorphCubeLoadsItsBaseMeshAndItsMorphAnimation) {
  ANAMORPH_REQUIRE_SHARED();
  const LoadedModel m = load_model(scene("gltf/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf"));
  EXPECT_EQ(m.triangle_count(), 12u);
  ASSERT_EQ(m.instances.size(), 1u);
  // Its weights animation is read (no warning), the mesh deforms.
  EXPECT_FALSE(test::has_warning(m, "animation")) << test::all_warnings(m);
  ASSERT_TRUE(m.rig);
  EXPECT_TRUE(m.rig->animated());
  EXPECT_EQ(m.rig->deformers.size(), 1u);
  expect_unit_normals(m);
}

TEST(SharedModels, TextureTransformTestAppliesTheExtension) {
  ANAMORPH_REQUIRE_SHARED();
  const LoadedModel m =
      load_model(scene("gltf/TextureTransformTest-glTF/TextureTransformTest.gltf"));
  size_t transformed = 0;
  for (const Material& mat : test::each(m.materials))
    if (mat.base_color.kind == Texture::Kind::Image && !mat.base_color.uv_transform.identity())
      ++transformed;
  EXPECT_GE(transformed, 5u) << "of " << m.materials.size() << " materials";
  for (const Material& mat : test::each(m.materials)) {
    if (mat.name != "Offset U") continue;
    const Vec2 o = mat.base_color.uv_transform.apply({0, 0});
    EXPECT_DOUBLE_EQ(o.x, 0.5);
    EXPECT_DOUBLE_EQ(o.y, 0.0);
    EXPECT_EQ(mat.base_color.wrap_s, Wrap::Clamp);
  }
}

TEST(SharedModels, BoxBadNormalsRepairedWithOneWarning) {
  ANAMORPH_REQUIRE_SHARED();
  const auto file = scene("gltf/robustness/BoxBadNormals.glb");
  const LoadedModel m = load_model(file);
  EXPECT_EQ(m.triangle_count(), 12u);
  expect_unit_normals(m);
  const auto n = std::count_if(m.warnings.begin(), m.warnings.end(), [&](const std::string& w) {
    return w.find("normals recomputed") != std::string::npos;
  });
  EXPECT_EQ(n, 1) << test::all_warnings(m);
  EXPECT_TRUE(test::has_warning(m, file.string())) << test::all_warnings(m);
  // A box: every repaired normal is the normal of a face it belongs to.
  const TriangleMesh& tm = m.prototypes.at(0).meshes.at(0);
  for (size_t t = 0; t < tm.triangle_count(); ++t) {
    const Vec3 a = Vec3(tm.positions[tm.indices[3 * t]]),
               b = Vec3(tm.positions[tm.indices[3 * t + 1]]),
               c = Vec3(tm.positions[tm.indices[3 * t + 2]]);
    const Vec3 fn = normalize(cross(b - a, c - a));
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(dot(Vec3(tm.normals[tm.indices[3 * t + k]]), fn), 1.0, 1e-5) << "triangle " << t;
  }
}

TEST(SharedModels, BoxWithInfinitesIsALoadError) {
  ANAMORPH_REQUIRE_SHARED();
  const auto file = scene("gltf/robustness/BoxWithInfinites.glb");
  try {
    load_model(file);
    FAIL() << "no LoadError";
  } catch (const LoadError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(file.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find("non-finite"), std::string::npos) << msg;
    EXPECT_NE(msg.find("mesh 'Mesh'"), std::string::npos) << msg;
  }
}

TEST(SharedModels, CornellBoxObj) {
  ANAMORPH_REQUIRE_SHARED();
  const LoadedModel m = load_model(scene("obj/cornell_box/cornell_box.obj"));
  EXPECT_EQ(m.triangle_count(), 36u);
  // The MTL defines 5 materials; "blue" is only named by the front wall, whose face is
  // commented out, so the 4 materials the geometry uses are loaded.
  std::set<std::string> names;
  for (const Material& mat : test::each(m.materials)) names.insert(mat.name);
  EXPECT_EQ(names, (std::set<std::string>{"white", "red", "green", "light"}));
  for (const Material& mat : test::each(m.materials)) {
    EXPECT_EQ(mat.type(), WhittedMaterial::kType);
    EXPECT_EQ(mat.is_emissive(), mat.name == "light") << mat.name;
    if (mat.name == "light") {
      EXPECT_EQ(mat.emission.value, Color(20, 20, 20));
    }
    if (mat.name == "red") {
      EXPECT_EQ(mat.base_color.value, Color(1, 0, 0));
    }
  }
  const Bounds3 b = placed_bounds(m);
  EXPECT_NEAR(b.hi.y, 548.8, 1e-3) << str(b.hi);
  EXPECT_NEAR(b.lo.y, 0, 1e-3) << str(b.lo);
  expect_unit_normals(m);
}

TEST(SharedModels, CubeTinyObj) {
  ANAMORPH_REQUIRE_SHARED();
  const LoadedModel m = load_model(scene("obj/cube_tinyobj/cube.obj"));
  EXPECT_EQ(m.triangle_count(), 12u);
  EXPECT_EQ(m.materials.size(), 3u);
  const Bounds3 b = placed_bounds(m);
  EXPECT_EQ(b.lo, Vec3(0, 0, 0));
  EXPECT_EQ(b.hi, Vec3(2, 2, 2));
}

TEST(SharedModels, CubePlyAsciiAndBinaryAgree) {
  ANAMORPH_REQUIRE_SHARED();
  const LoadedModel a = load_model(scene("ply/assimp/cube.ply"));
  const LoadedModel b = load_model(scene("ply/assimp/cube_binary.ply"));
  EXPECT_EQ(a.triangle_count(), 12u);
  EXPECT_EQ(b.triangle_count(), 12u);
  const Bounds3 ba = placed_bounds(a), bb = placed_bounds(b);
  EXPECT_EQ(ba.lo, bb.lo) << str(ba.lo) << " vs " << str(bb.lo);
  EXPECT_EQ(ba.hi, bb.hi) << str(ba.hi) << " vs " << str(bb.hi);
  // PLY has no materials: our default grey, not assimp's white with a full highlight.
  ASSERT_EQ(a.materials.size(), 1u);
  EXPECT_EQ(test::material_as<WhittedMaterial>(*a.materials[0]).specular, Color(0, 0, 0));
}

TEST(SharedModels, BunnyWithExtraVertexProperties) {
  ANAMORPH_REQUIRE_SHARED();
  const LoadedModel m = load_model(scene("ply/stanford_bunny/bun_zipper_res4.ply"));
  EXPECT_EQ(m.triangle_count(), 948u);
  expect_unit_normals(m);
  ASSERT_EQ(m.prototypes.size(), 1u);
  EXPECT_FALSE(m.prototypes[0].meshes.at(0).normals.empty());
}

}  // namespace
}  // namespace anamorph
