// A glTF file as a whole scene (`anamorph render scene.glb`, scene/gltf_scene.h) and a scene
// file's [[material]] overriding a glTF material by name (docs/gltf.md, precedence).
#include <gtest/gtest.h>

#include <string>

#include "loader_fixture.h"
#include "material/metallic_roughness.h"
#include "scene/scene_loader.h"
#include "scene/toml_reader.h"
#include "test_util.h"

namespace anamorph {
namespace {

using test::GltfWriter;
using test::ScratchDir;
using test::str;

std::filesystem::path blender(const std::string& name) {
  return test::data_dir() / "gltf/blender" / (name + ".glb");
}

// The same file as the object of a scene file that names its camera.
std::string scene_text(const std::string& name, const std::string& extra = "") {
  return "[image]\nwidth = 160\nheight = 120\n[camera]\ngltf_camera = 0\n[[object]]\ntype = "
         "\"mesh\"\nfile = \"" +
         blender(name).string() + "\"\n" + extra;
}

TEST(GltfScene, DefaultsAreThePathTracerTheWorldAndTheFilesCamera) {
  const Scene s = load_scene(blender("studio"), {"image.width=160"});
  EXPECT_EQ(s.render.integrator, "path");
  EXPECT_EQ(s.render.spp, 64);
  EXPECT_EQ(s.render.max_depth, 9);
  EXPECT_EQ(s.render.antialias, Antialias::Uniform);
  EXPECT_EQ(s.environment.color.x, 0.05);
  EXPECT_EQ(s.lights.size(), 3u);
  // The height follows the camera's aspectRatio (4:3 at export).
  EXPECT_EQ(s.render.height, 120);
  // The camera is the file's: every point projects where a scene file's gltf_camera = 0 puts it.
  const Scene ref = load_scene_from_string(scene_text("studio"), "t.toml");
  for (const Vec3& p : {Vec3{0, 0.5, 0}, Vec3{1, 1, -1}, Vec3{-1.5, 0.2, 0.5}}) {
    const auto a = s.camera->project(p), b = ref.camera->project(p);
    ASSERT_EQ(a.size(), 1u) << str(p);
    ASSERT_EQ(b.size(), 1u) << str(p);
    EXPECT_NEAR(a[0].x, b[0].x, 1e-12) << str(p);
    EXPECT_NEAR(a[0].y, b[0].y, 1e-12) << str(p);
  }
}

// An image wider than the camera's aspectRatio (8:3 against 4:3) shows more to the sides and
// stretches nothing: every point lies as many pixels from the centre as in the 4:3 image.
TEST(GltfScene, AnotherImageShapeWidensTheViewWithoutStretching) {
  const Scene narrow = load_scene(blender("studio"), {"image.width=160"});
  const Scene wide = load_scene(blender("studio"), {"image.width=320", "image.height=120"});
  ASSERT_EQ(narrow.render.height, 120);
  for (const Vec3& p : {Vec3{0, 0.5, 0}, Vec3{1, 1, -1}, Vec3{-1.5, 0.2, 0.5}}) {
    const auto a = narrow.camera->project(p), b = wide.camera->project(p);
    ASSERT_EQ(a.size(), 1u) << str(p);
    ASSERT_EQ(b.size(), 1u) << str(p);
    EXPECT_NEAR((a[0].x - 0.5) * 160, (b[0].x - 0.5) * 320, 1e-9) << str(p);
    EXPECT_NEAR(a[0].y, b[0].y, 1e-12) << str(p);
  }
}

TEST(GltfScene, OverridesChangeWhatGltfCannotSay) {
  const Scene s =
      load_scene(blender("studio"), {"image.width=120", "image.height=120", "camera.preset=fisheye",
                                     "environment.color=[0.1, 0.2, 0.3]", "render.spp=4"});
  EXPECT_EQ(s.render.height, 120);  // given: the camera's aspect does not change it
  EXPECT_EQ(s.render.spp, 4);
  EXPECT_EQ(s.environment.color.z, 0.3);
  // The preset rides the file's camera.
  EXPECT_NE(s.camera->describe().find("at glTF camera"), std::string::npos) << s.camera->describe();
}

// Without a camera (here: the file's cameras dropped), a view framing the whole scene: every
// corner of its bounding box projects inside the image.
TEST(GltfScene, WithoutACameraTheViewFramesTheScene) {
  for (const char* size : {"image.height=120", "image.height=300"}) {
    const Scene s =
        load_scene(blender("point_only"), {"object.0.cameras=false", "image.width=160", size});
    ASSERT_TRUE(s.model_cameras.empty());
    Bounds3 box;
    for (const Instance& inst : s.instances)
      for (const TriangleMesh& m : s.prototypes[inst.prototype].meshes)
        for (const Vec3f& p : m.positions) box.extend(inst.world_from_object.point(Vec3(p)));
    ASSERT_FALSE(box.empty());
    for (int k = 0; k < 8; ++k) {
      const Vec3 p{k & 1 ? box.hi.x : box.lo.x, k & 2 ? box.hi.y : box.lo.y,
                   k & 4 ? box.hi.z : box.lo.z};
      const auto uv = s.camera->project(p);
      ASSERT_EQ(uv.size(), 1u) << size << ": corner " << str(p) << " not in the image";
      EXPECT_GE(uv[0].x, 0) << str(p);
      EXPECT_LE(uv[0].x, 1) << str(p);
      EXPECT_GE(uv[0].y, 0) << str(p);
      EXPECT_LE(uv[0].y, 1) << str(p);
    }
    // ... and the centre at the image's centre.
    const auto c = s.camera->project(box.center());
    ASSERT_EQ(c.size(), 1u);
    EXPECT_NEAR(c[0].x, 0.5, 1e-9);
    EXPECT_NEAR(c[0].y, 0.5, 1e-9);
  }
}

TEST(GltfScene, SceneMaterialOfTheSameNameOverridesTheGltfMaterial) {
  const Scene s = load_scene_from_string(
      "[[material]]\nname = \"glass\"\ntype = \"whitted\"\ncolor = [0.1, 0.9, 0.1]\n" +
          scene_text("studio"),
      "t.toml");
  int named = 0;
  for (const auto& m : s.materials) named += m->name == "glass";
  EXPECT_EQ(named, 1) << "a second material named glass was added";
  const Material* glass = nullptr;
  for (const Prototype& p : s.prototypes)
    for (const TriangleMesh& m : p.meshes)
      if (s.materials[m.material]->name == "glass") glass = s.materials[m.material].get();
  ASSERT_NE(glass, nullptr) << "no mesh uses the glass material";
  EXPECT_EQ(glass->type(), "whitted");
  EXPECT_EQ(glass->base_color.value.y, 0.9);
  // The file's other materials stay its own.
  for (const auto& m : s.materials) {
    if (m->name == "gold") {
      EXPECT_EQ(m->type(), MetallicRoughnessMaterial::kType);
    }
  }
}

TEST(GltfScene, OverrideNamingTwoGltfMaterialsIsAnErrorAtItsName) {
  ScratchDir dir;
  GltfWriter w;
  const std::vector<float> quad = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  const int pos = w.floats(quad, "VEC3");
  const int idx = w.indices(std::vector<uint16_t>{0, 1, 2, 0, 2, 3});
  w.j["materials"] = {{{"name", "dup"}}, {{"name", "dup"}}, {{"name", "other"}}};
  w.node({{"mesh", w.mesh({{"POSITION", pos}}, idx, 0, 4, "a")}});
  w.node({{"mesh", w.mesh({{"POSITION", pos}}, idx, 1, 4, "b")}});
  const auto file = dir.write("dup.gltf", w.text());
  const std::string object = "[[object]]\ntype = \"mesh\"\nfile = \"" + file.string() + "\"\n";
  // Without an override both load (glTF names need not be unique).
  EXPECT_NO_THROW(load_scene_from_string(object, dir.path() / "ok.toml"));
  const std::string text = "[[material]]\nname = \"x\"\n[[material]]\nname = \"dup\"\n" + object;
  try {
    load_scene_from_string(text, dir.path() / "dup.toml");
    FAIL() << "an ambiguous override loaded";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.loc.line, 4) << e.what();
    EXPECT_EQ(e.loc.column, 8) << e.what();
    EXPECT_EQ(e.key, "material[1].name") << e.what();
    EXPECT_NE(e.message.find("materials 0 and 1"), std::string::npos) << e.what();
  }
}

// The shared Khronos samples as whole scenes (`render X.gltf`): they load with no warning (all
// they use is read, ClearCoatTest's KHR_materials_clearcoat too), and the framing view (none has
// a camera) sees every one of their objects.
TEST(GltfScene, SharedKhronosSamplesLoadWithoutWarningsForWhatIsSupported) {
  ANAMORPH_REQUIRE_SHARED();
  for (const char* f :
       {"gltf/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf",
        "gltf/TextureTransformTest-glTF/TextureTransformTest.gltf",
        "gltf/ClearCoatTest-glTF/ClearCoatTest.gltf", "gltf/BoxTextured-glTF/BoxTextured.gltf"}) {
    const Scene s = load_scene(test::shared_scenes() / f, {"image.width=32"});
    for (const std::string& w : s.warnings) ADD_FAILURE() << f << ": " << w;
    EXPECT_EQ(s.render.height, 24) << f;
    ASSERT_FALSE(s.instances.empty()) << f;
    for (const Instance& inst : s.instances) {
      const auto uv = s.camera->project(inst.world_from_object.point({0, 0, 0}));
      EXPECT_EQ(uv.size(), 1u) << f << ": " << inst.name << " outside the framing view";
    }
  }
}

}  // namespace
}  // namespace anamorph
