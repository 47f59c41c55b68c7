// assimp loader on fixtures made here: uv orientation, MTL materials, generated normals,
// node instancing, the OBJ emission convention and errors.
#include <gtest/gtest.h>

#include "loader_fixture.h"
#include "material/whitted.h"
#include "material_util.h"
#include "scene/loaders.h"
#include "test_util.h"

namespace anamorph {
namespace {

using test::face_normal;
using test::ScratchDir;
using test::str;

Color texel(const Texture& t, Vec2 uv) {
  TexCoord tc;
  tc.uv = uv;
  return t.eval(tc);
}

TEST(AssimpLoader, ObjUvsAreFlippedSoTheImageTopIsUvZero) {
  const LoadedModel m = load_model(test::data_dir() / "models/textured_quad.obj");
  ASSERT_EQ(m.prototypes.size(), 1u);
  ASSERT_EQ(m.instances.size(), 1u);
  const TriangleMesh& tm = m.prototypes[0].meshes.at(0);
  ASSERT_EQ(tm.uvs.size(), tm.positions.size());
  EXPECT_EQ(tm.triangle_count(), 2u);
  // OBJ vt = (x, y) at position (x, y, 0); stored uv = (vt.u, 1 - vt.v).
  for (size_t i = 0; i < tm.positions.size(); ++i) {
    const Vec3f p = tm.positions[i];
    EXPECT_EQ(tm.uvs[i], Vec2f(p.x, 1 - p.y)) << "vertex " << i << " at " << str(Vec3(p));
  }
  ASSERT_EQ(m.materials.size(), 1u);
  const Material& mat = *m.materials[0];
  EXPECT_EQ(mat.name, "quadrants");
  EXPECT_EQ(mat.type(), WhittedMaterial::kType);
  const auto& whitted = test::material_as<WhittedMaterial>(mat);
  EXPECT_EQ(whitted.specular, Color(0.5, 0.5, 0.5));
  EXPECT_DOUBLE_EQ(whitted.exponent, 20);
  ASSERT_EQ(mat.base_color.kind, Texture::Kind::Image);
  // The corner at (0, 1, 0), top-left in the y-up plane, shows the image's top-left: red.
  for (size_t i = 0; i < tm.positions.size(); ++i) {
    if (tm.positions[i] != Vec3f{0, 1, 0}) continue;
    const Vec2 uv{tm.uvs[i].x + 0.25, tm.uvs[i].y + 0.25};  // the centre of its texel
    const Color c = texel(mat.base_color, uv);
    EXPECT_NEAR(c.x, 1, 0.05) << str(c);
    EXPECT_NEAR(c.z, 0, 0.05) << str(c);
  }
  EXPECT_TRUE(m.warnings.empty()) << test::all_warnings(m);
}

TEST(AssimpLoader, MissingNormalsAreSmoothButKeepHardEdges) {
  ScratchDir dir;
  // A cube with shared corners (8 vertices) and a gently folded strip (10 degrees).
  const auto cube = dir.write("cube.ply", R"(ply
format ascii 1.0
element vertex 8
property float x
property float y
property float z
element face 6
property list uchar int vertex_indices
end_header
0 0 0
1 0 0
1 1 0
0 1 0
0 0 1
1 0 1
1 1 1
0 1 1
4 0 3 2 1
4 4 5 6 7
4 0 1 5 4
4 2 3 7 6
4 1 2 6 5
4 0 4 7 3
)");
  const LoadedModel m = load_model(cube);
  const TriangleMesh& tm = m.prototypes.at(0).meshes.at(0);
  EXPECT_EQ(tm.triangle_count(), 12u);
  ASSERT_EQ(tm.normals.size(), tm.positions.size());
  // 90 degree edges are beyond the crease: every corner normal is its face's normal.
  for (size_t t = 0; t < tm.triangle_count(); ++t)
    for (int k = 0; k < 3; ++k) {
      const Vec3 n = Vec3(tm.normals[tm.indices[3 * t + k]]);
      EXPECT_NEAR(length(n - face_normal(tm, t)), 0, 1e-6) << "triangle " << t << " " << str(n);
    }
  EXPECT_EQ(tm.positions.size(), 24u);  // each corner split into 3

  const auto fold = dir.write("fold.obj", R"(v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 2 0 0.17633
v 2 1 0.17633
f 1 2 3 4
f 2 5 6 3
)");
  const LoadedModel f = load_model(fold);
  const TriangleMesh& fm = f.prototypes.at(0).meshes.at(0);
  // On the shared edge x = 1 the normal is the average of both sides (about 5 degrees off z).
  for (size_t i = 0; i < fm.positions.size(); ++i) {
    const Vec3 n = Vec3(fm.normals[i]);
    EXPECT_NEAR(length(n), 1, 1e-6);
    if (fm.positions[i].x == 1) {
      EXPECT_LT(n.x, -0.01) << str(n);
      EXPECT_GT(n.z, 0.99) << str(n);
    }
  }
}

TEST(AssimpLoader, MeshSharedByNodesIsOnePrototypePlacedTwice) {
  ScratchDir dir;
  const auto dae = dir.write("two.dae", R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Y_UP</up_axis></asset>
  <library_geometries>
    <geometry id="tri" name="tri"><mesh>
      <source id="p"><float_array id="pa" count="9">0 0 0 1 0 0 0 1 0</float_array>
        <technique_common><accessor source="#pa" count="3" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common></source>
      <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
      <triangles count="1"><input semantic="VERTEX" source="#v" offset="0"/><p>0 1 2</p></triangles>
    </mesh></geometry>
    <geometry id="once" name="once"><mesh>
      <source id="q"><float_array id="qa" count="9">0 0 0 1 0 0 0 1 0</float_array>
        <technique_common><accessor source="#qa" count="3" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common></source>
      <vertices id="w"><input semantic="POSITION" source="#q"/></vertices>
      <triangles count="1"><input semantic="VERTEX" source="#w" offset="0"/><p>0 1 2</p></triangles>
    </mesh></geometry>
  </library_geometries>
  <library_visual_scenes><visual_scene id="s">
    <node id="a" name="a"><translate>2 0 0</translate><instance_geometry url="#tri"/></node>
    <node id="b" name="b"><translate>0 3 0</translate><instance_geometry url="#tri"/></node>
    <node id="c" name="c"><translate>0 0 7</translate><instance_geometry url="#once"/></node>
  </visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
)");
  const LoadedModel m = load_model(dae);
  // "tri" built once and placed by a and b; "once" baked into the file's main prototype.
  ASSERT_EQ(m.prototypes.size(), 2u);
  ASSERT_EQ(m.instances.size(), 3u);
  EXPECT_EQ(m.triangle_count(), 2u);
  std::vector<Vec3> placed;
  for (const Instance& in : m.instances)
    if (m.prototypes.at(in.prototype).name == "tri")
      placed.push_back(in.world_from_object.point({1, 0, 0}));
  ASSERT_EQ(placed.size(), 2u);
  EXPECT_NEAR(length(placed[0] - Vec3{3, 0, 0}), 0, 1e-6) << str(placed[0]);
  EXPECT_NEAR(length(placed[1] - Vec3{1, 3, 0}), 0, 1e-6) << str(placed[1]);
  const Prototype& main = m.prototypes.at(1);
  EXPECT_EQ(main.name, "two");
  for (const Vec3f& p : main.meshes.at(0).positions) EXPECT_FLOAT_EQ(p.z, 7);  // baked
}

TEST(AssimpLoader, ObjAmbientAboveOneIsEmissionOnlyWithoutKe) {
  ScratchDir dir;
  dir.write("l.mtl", R"(newmtl lamp
Ka 2 3 4
Kd 0.5 0.5 0.5
newmtl dim
Ka 0.9 0.9 0.9
Kd 0.5 0.5 0.5
newmtl glow
Ka 5 5 5
Ke 1 0 0
)");
  const auto obj = dir.write("l.obj", R"(mtllib l.mtl
v 0 0 0
v 1 0 0
v 0 1 0
v 0 0 1
v 1 0 1
v 0 1 1
v 0 0 2
v 1 0 2
v 0 1 2
usemtl lamp
f 1 2 3
usemtl dim
f 4 5 6
usemtl glow
f 7 8 9
)");
  const LoadedModel m = load_model(obj);
  ASSERT_EQ(m.materials.size(), 3u);
  for (const Material& mat : test::each(m.materials)) {
    if (mat.name == "lamp") {
      EXPECT_EQ(mat.emission.value, Color(2, 3, 4));
    }
    if (mat.name == "dim") {
      EXPECT_FALSE(mat.is_emissive());
    }
    if (mat.name == "glow") {
      EXPECT_EQ(mat.emission.value, Color(1, 0, 0));  // Ke wins
    }
  }
  EXPECT_TRUE(test::has_warning(m, "'lamp'")) << test::all_warnings(m);
  EXPECT_FALSE(test::has_warning(m, "'glow'")) << test::all_warnings(m);
}

TEST(AssimpLoader, UnreadableTextureIsAWarningAndKdRemains) {
  ScratchDir dir;
  dir.write("t.mtl", "newmtl m\nKd 0.25 0.5 0.75\nmap_Kd textures\\gone.png\n");
  const auto obj =
      dir.write("t.obj", "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n");
  const LoadedModel m = load_model(obj);
  ASSERT_EQ(m.materials.size(), 1u);
  EXPECT_EQ(m.materials[0]->base_color.kind, Texture::Kind::Constant);
  EXPECT_EQ(m.materials[0]->base_color.value, Color(0.25, 0.5, 0.75));
  // The Windows separator is read as a directory separator.
  EXPECT_TRUE(test::has_warning(m, "textures/gone.png")) << test::all_warnings(m);
}

TEST(AssimpLoader, OutOfRangeObjIndexIsALoadError) {
  ScratchDir dir;
  // assimp rejects faces that name missing vertices; the loader must turn that into a LoadError.
  const auto obj = dir.write("oor.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
  try {
    load_model(obj);
    FAIL() << "no LoadError";
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find(obj.string()), std::string::npos) << e.what();
  }
}

TEST(AssimpLoader, MissingAndGarbageFilesAreLoadErrorsNamingTheFile) {
  ScratchDir dir;
  const auto missing = dir.path() / "absent.obj";
  try {
    load_model(missing);
    FAIL() << "no LoadError";
  } catch (const LoadError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("cannot open " + missing.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find("No such file"), std::string::npos) << msg;
  }
  for (const char* name : {"garbage.ply", "garbage.stl", "garbage.xyz"}) {
    const auto file = dir.write(name, std::string("\x7f\x00\x13 not a mesh \xff\xfe", 17));
    try {
      load_model(file);
      ADD_FAILURE() << name << ": no LoadError";
    } catch (const LoadError& e) {
      EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace anamorph
