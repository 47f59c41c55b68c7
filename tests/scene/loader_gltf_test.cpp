// glTF loader on fixtures made here (committed ones in tests/data/models, generated ones written
// by the tests), so the core is covered without ../shared.
#include <cmath>

#include <gtest/gtest.h>

#include "io/image_io.h"
#include "loader_fixture.h"
#include "material/metallic_roughness.h"
#include "material_util.h"
#include "scene/loaders.h"
#include "test_util.h"

namespace anamorph {
namespace {

using nlohmann::json;
using test::face_normal;
using test::GltfWriter;
using test::ScratchDir;
using test::str;

const std::vector<float> kQuad = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
int quad_indices(GltfWriter& w) { return w.indices(std::vector<uint16_t>{0, 1, 2, 0, 2, 3}); }

Color texel(const Texture& t, Vec2 uv, double* alpha = nullptr) {
  TexCoord tc;
  tc.uv = uv;
  return t.eval(tc, alpha);
}

TEST(GltfLoader, MeshUsedByTwoNodesIsOnePrototypeWithTwoInstances) {
  const LoadedModel m = load_model(test::data_dir() / "models/shared_mesh.gltf");
  ASSERT_EQ(m.prototypes.size(), 1u);
  ASSERT_EQ(m.instances.size(), 2u);
  EXPECT_EQ(m.prototypes[0].name, "quad");
  ASSERT_EQ(m.prototypes[0].meshes.size(), 1u);
  EXPECT_EQ(m.triangle_count(), 2u);
  EXPECT_EQ(m.instances[0].prototype, 0u);
  EXPECT_EQ(m.instances[1].prototype, 0u);
  EXPECT_EQ(m.instances[0].name, "a");
  EXPECT_EQ(m.instances[1].name, "b");
  // a: translation (2,0,0); b: matrix = scale 2 then translate (0,3,0).
  const Vec3 pa = m.instances[0].world_from_object.point({1, 1, 0});
  const Vec3 pb = m.instances[1].world_from_object.point({1, 1, 0});
  EXPECT_NEAR(length(pa - Vec3{3, 1, 0}), 0, 1e-12) << str(pa);
  EXPECT_NEAR(length(pb - Vec3{2, 5, 0}), 0, 1e-12) << str(pb);
  ASSERT_EQ(m.materials.size(), 1u);
  EXPECT_EQ(m.materials[0]->type(), MetallicRoughnessMaterial::kType);
  EXPECT_DOUBLE_EQ(m.materials[0]->base_color.value.x, 0.5);
  EXPECT_DOUBLE_EQ(test::material_as<MetallicRoughnessMaterial>(*m.materials[0]).metallic, 0);
  EXPECT_TRUE(m.warnings.empty()) << test::all_warnings(m);
}

TEST(GltfLoader, IndicesOfEveryComponentTypeGiveTheSameTriangles) {
  ScratchDir dir;
  const std::vector<uint32_t> want = {0, 1, 2, 0, 2, 3};
  for (int kind = 0; kind < 3; ++kind) {
    GltfWriter w;
    const int p = w.floats(kQuad, "VEC3");
    int idx = -1;
    if (kind == 0) idx = w.indices(std::vector<uint8_t>{0, 1, 2, 0, 2, 3});
    if (kind == 1) idx = w.indices(std::vector<uint16_t>{0, 1, 2, 0, 2, 3});
    if (kind == 2) idx = w.indices(std::vector<uint32_t>{0, 1, 2, 0, 2, 3});
    w.node({{"mesh", w.mesh({{"POSITION", p}}, idx)}});
    const LoadedModel m = load_gltf(dir.write(fmt::format("i{}.gltf", kind), w.text()));
    ASSERT_EQ(m.prototypes.size(), 1u);
    EXPECT_EQ(m.prototypes[0].meshes[0].indices, want) << "index component kind " << kind;
    // No material: glTF's default material is added.
    ASSERT_EQ(m.materials.size(), 1u);
    EXPECT_EQ(m.materials[0]->name, "glTF default");
  }
}

TEST(GltfLoader, NonIndexedStripAndFanBecomeTrianglesWithOneWinding) {
  ScratchDir dir;
  // Strip 0,1,3,2 and fan 0,1,2,3 both cover the unit quad, counter-clockwise seen from +z.
  const std::vector<float> strip = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  for (int mode : {5, 6}) {
    GltfWriter w;
    const int p = w.floats(mode == 5 ? strip : kQuad, "VEC3");
    w.node({{"mesh", w.mesh({{"POSITION", p}}, -1, -1, mode)}});
    const LoadedModel m = load_gltf(dir.write("s.gltf", w.text()));
    ASSERT_EQ(m.prototypes.size(), 1u);
    const TriangleMesh& tm = m.prototypes[0].meshes[0];
    ASSERT_EQ(tm.triangle_count(), 2u) << "mode " << mode;
    for (size_t t = 0; t < 2; ++t)
      EXPECT_NEAR(face_normal(tm, t).z, 1.0, 1e-12) << "mode " << mode << " triangle " << t;
  }
}

TEST(GltfLoader, PointAndLinePrimitivesAreSkippedWithAWarning) {
  ScratchDir dir;
  GltfWriter w;
  const int p = w.floats(kQuad, "VEC3");
  w.mesh({{"POSITION", p}}, w.indices(std::vector<uint8_t>{0, 1, 2}), -1, 4);
  w.j["meshes"][0]["primitives"].push_back({{"attributes", {{"POSITION", p}}}, {"mode", 1}});
  w.node({{"mesh", 0}});
  const LoadedModel m = load_gltf(dir.write("l.gltf", w.text()));
  ASSERT_EQ(m.prototypes.size(), 1u);
  EXPECT_EQ(m.prototypes[0].meshes.size(), 1u);
  EXPECT_EQ(m.triangle_count(), 1u);
  EXPECT_TRUE(test::has_warning(m, "mode 1")) << test::all_warnings(m);
}

TEST(GltfLoader, SparseAccessorWithoutBufferViewStartsFromZeros) {
  ScratchDir dir;
  GltfWriter w;
  // Four positions, all zero except vertices 1, 2, 3 given sparsely: the unit quad.
  const int iv = w.view(test::bytes_of(std::vector<uint16_t>{1, 2, 3}));
  const int vv = w.view(test::bytes_of(std::vector<float>{1, 0, 0, 1, 1, 0, 0, 1, 0}));
  const int p = w.accessor(-1, 5126, 4, "VEC3",
                           {{"sparse",
                             {{"count", 3},
                              {"indices", {{"bufferView", iv}, {"componentType", 5123}}},
                              {"values", {{"bufferView", vv}}}}}});
  w.node({{"mesh", w.mesh({{"POSITION", p}}, w.indices(std::vector<uint8_t>{0, 1, 2, 0, 2, 3}))}});
  const LoadedModel m = load_gltf(dir.write("sp.gltf", w.text()));
  ASSERT_EQ(m.prototypes.size(), 1u);
  const TriangleMesh& tm = m.prototypes[0].meshes[0];
  ASSERT_EQ(tm.positions.size(), 4u);
  for (size_t i = 0; i < 4; ++i) {
    const Vec3 want{kQuad[3 * i], kQuad[3 * i + 1], kQuad[3 * i + 2]};
    EXPECT_EQ(test::pos(tm, i), want) << "vertex " << i << " " << str(test::pos(tm, i));
  }
}

TEST(GltfLoader, InterleavedStrideAndNormalizedTexcoords) {
  ScratchDir dir;
  GltfWriter w;
  // Interleaved: position (3 floats) + normal (3 floats), stride 24.
  std::vector<float> inter;
  for (size_t i = 0; i < 4; ++i) {
    inter.insert(inter.end(), {kQuad[3 * i], kQuad[3 * i + 1], kQuad[3 * i + 2]});
    inter.insert(inter.end(), {0, 0, 2});  // not unit: must come back normalized
  }
  const int v = w.view(test::bytes_of(inter), 24);
  const int p = w.accessor(v, 5126, 4, "VEC3");
  const int n = w.accessor(v, 5126, 4, "VEC3", {{"byteOffset", 12}});
  // u16 normalized texcoords: 65535 = 1.
  const int t = w.accessor(
      w.view(test::bytes_of(std::vector<uint16_t>{0, 0, 65535, 0, 65535, 65535, 0, 32768})), 5123,
      4, "VEC2", {{"normalized", true}});
  w.node({{"mesh", w.mesh({{"POSITION", p}, {"NORMAL", n}, {"TEXCOORD_0", t}},
                          w.indices(std::vector<uint16_t>{0, 1, 2, 0, 2, 3}))}});
  const LoadedModel m = load_gltf(dir.write("st.gltf", w.text()));
  const TriangleMesh& tm = m.prototypes.at(0).meshes.at(0);
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(test::pos(tm, i), Vec3(kQuad[3 * i], kQuad[3 * i + 1], kQuad[3 * i + 2])) << i;
    EXPECT_EQ(Vec3(tm.normals[i]), Vec3(0, 0, 1)) << i;
  }
  EXPECT_EQ(tm.uvs[2], Vec2f(1, 1));
  EXPECT_NEAR(tm.uvs[3].y, 32768.0 / 65535.0, 1e-7);
}

TEST(GltfLoader, OutOfRangeIndexIsALoadErrorNamingFileAndMesh) {
  ScratchDir dir;
  GltfWriter w;
  const int p = w.floats(kQuad, "VEC3");
  w.node({{"mesh", w.mesh({{"POSITION", p}}, w.indices(std::vector<uint16_t>{0, 1, 7}), -1, 4,
                          "bad_indices")}});
  const auto file = dir.write("oor.gltf", w.text());
  try {
    load_gltf(file);
    FAIL() << "no LoadError";
  } catch (const LoadError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(file.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find("bad_indices"), std::string::npos) << msg;
    EXPECT_NE(msg.find("out of range"), std::string::npos) << msg;
  }
}

TEST(GltfLoader, AccessorOverrunningItsBufferViewIsALoadError) {
  ScratchDir dir;
  GltfWriter w;
  const int v = w.view(test::bytes_of(kQuad));
  const int p = w.accessor(v, 5126, 5, "VEC3");  // 5 elements, 4 stored
  w.node({{"mesh", w.mesh({{"POSITION", p}})}});
  EXPECT_THROW(load_gltf(dir.write("over.gltf", w.text())), LoadError);
}

TEST(GltfLoader, DegenerateTrianglesAreDroppedWithOneCountingWarning) {
  ScratchDir dir;
  GltfWriter w;
  // Vertex 4 lies on the edge 0-1: triangle (0,1,4) is collinear; (0,0,2) repeats an index.
  std::vector<float> pts = kQuad;
  pts.insert(pts.end(), {0.5f, 0, 0});
  const int p = w.floats(pts, "VEC3");
  w.node({{"mesh", w.mesh({{"POSITION", p}},
                          w.indices(std::vector<uint16_t>{0, 1, 2, 0, 1, 4, 0, 0, 2}))}});
  const auto file = dir.write("deg.gltf", w.text());
  const LoadedModel m = load_gltf(file);
  EXPECT_EQ(m.triangle_count(), 1u);
  EXPECT_EQ(m.prototypes.at(0).meshes.at(0).indices, (std::vector<uint32_t>{0, 1, 2}));
  EXPECT_TRUE(test::has_warning(m, "2 degenerate")) << test::all_warnings(m);
  EXPECT_TRUE(test::has_warning(m, file.string())) << test::all_warnings(m);
}

TEST(GltfLoader, NonFinitePositionsAreALoadError) {
  ScratchDir dir;
  GltfWriter w;
  std::vector<float> pts = kQuad;
  pts[4] = std::numeric_limits<float>::infinity();
  w.node(
      {{"mesh", w.mesh({{"POSITION", w.floats(pts, "VEC3")}}, quad_indices(w), -1, 4, "spiky")}});
  const auto file = dir.write("inf.gltf", w.text());
  try {
    load_gltf(file);
    FAIL() << "no LoadError";
  } catch (const LoadError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("non-finite"), std::string::npos) << msg;
    EXPECT_NE(msg.find("spiky"), std::string::npos) << msg;
    EXPECT_NE(msg.find(file.string()), std::string::npos) << msg;
  }
}

TEST(GltfLoader, ZeroNormalsAreRecomputedFromTheFaces) {
  ScratchDir dir;
  GltfWriter w;
  const int p = w.floats(kQuad, "VEC3");
  const int n = w.floats({0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1}, "VEC3");
  w.node({{"mesh", w.mesh({{"POSITION", p}, {"NORMAL", n}},
                          w.indices(std::vector<uint16_t>{0, 1, 2, 0, 2, 3}))}});
  const LoadedModel m = load_gltf(dir.write("zn.gltf", w.text()));
  const TriangleMesh& tm = m.prototypes.at(0).meshes.at(0);
  for (size_t i = 0; i < 4; ++i) EXPECT_EQ(Vec3(tm.normals[i]), Vec3(0, 0, 1)) << i;
  EXPECT_TRUE(test::has_warning(m, "2 zero-length")) << test::all_warnings(m);
}

TEST(GltfLoader, MorphTargetsWithDefaultWeightsGiveTheStaticPose) {
  ScratchDir dir;
  GltfWriter w;
  const int p = w.floats(kQuad, "VEC3");
  const int d = w.floats({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3");
  w.mesh({{"POSITION", p}}, quad_indices(w));
  w.j["meshes"][0]["primitives"][0]["targets"] = {{{"POSITION", d}}};
  w.j["meshes"][0]["weights"] = {0.25};
  w.node({{"mesh", 0}});
  const LoadedModel m = load_gltf(dir.write("morph.gltf", w.text()));
  for (const Vec3f& q : m.prototypes.at(0).meshes.at(0).positions) EXPECT_FLOAT_EQ(q.z, 0.25f);
}

TEST(GltfLoader, NodeCycleIsALoadError) {
  ScratchDir dir;
  GltfWriter w;
  w.node({{"children", {1}}});
  w.j["nodes"].push_back({{"children", {0}}});
  EXPECT_THROW(load_gltf(dir.write("cycle.gltf", w.text())), LoadError);
}

TEST(GltfLoader, WithoutScenesEveryRootNodeIsPlaced) {
  ScratchDir dir;
  GltfWriter w;
  const int mesh = w.mesh({{"POSITION", w.floats(kQuad, "VEC3")}}, quad_indices(w));
  w.j["nodes"] = {
      {{"children", {1}}}, {{"mesh", mesh}}, {{"mesh", mesh}, {"translation", {0, 0, 5}}}};
  const LoadedModel m = load_gltf(dir.write("noscene.gltf", w.text()));
  EXPECT_EQ(m.prototypes.size(), 1u);
  EXPECT_EQ(m.instances.size(), 2u);  // node 1 via its parent 0, node 2 as a root
}

TEST(GltfLoader, CamerasArePlacedByTheirNodes) {
  ScratchDir dir;
  GltfWriter w;
  w.j["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}},
                    {{"type", "orthographic"},
                     {"orthographic", {{"xmag", 2}, {"ymag", 3}, {"znear", 0}, {"zfar", 9}}}}};
  // Rotation of 90 degrees about +y: the camera's -z view axis turns to -x.
  const double s = std::sqrt(0.5);
  w.node(
      {{"camera", 0}, {"translation", {1, 2, 3}}, {"rotation", {0, s, 0, s}}, {"name", "persp"}});
  w.node({{"camera", 1}});
  const LoadedModel m = load_gltf(dir.write("cams.gltf", w.text()));
  ASSERT_EQ(m.cameras.size(), 2u);
  EXPECT_TRUE(m.cameras[0].perspective);
  EXPECT_DOUBLE_EQ(m.cameras[0].yfov, 0.5);
  EXPECT_DOUBLE_EQ(m.cameras[0].aspect, 0);
  EXPECT_EQ(m.cameras[0].name, "persp");
  const Vec3 o = m.cameras[0].world_from_camera.point({0, 0, 0});
  const Vec3 f = m.cameras[0].world_from_camera.vector({0, 0, -1});
  EXPECT_NEAR(length(o - Vec3{1, 2, 3}), 0, 1e-12) << str(o);
  EXPECT_NEAR(length(f - Vec3{-1, 0, 0}), 0, 1e-12) << str(f);
  EXPECT_FALSE(m.cameras[1].perspective);
  EXPECT_DOUBLE_EQ(m.cameras[1].xmag, 2);
  EXPECT_DOUBLE_EQ(m.cameras[1].ymag, 3);
}

// One material exercising the texture paths; the image is tests/data/models/quadrants.png
// (TL red, TR green, BL blue, BR white) or grey128.png (128 in every channel).
class GltfMaterials : public ::testing::Test {
 protected:
  LoadedModel load(const json& material, const std::string& png, bool uv1 = false) {
    GltfWriter w;
    w.j["images"] = {{{"uri", "data:image/png;base64," + test::base64(test::read_bytes(
                                                             test::data_dir() / "models" / png))}}};
    w.j["samplers"] = {{{"wrapS", 33071}, {"wrapT", 33648}, {"magFilter", 9728}}};
    w.j["textures"] = {{{"source", 0}, {"sampler", 0}}, {{"source", 0}}};
    w.j["materials"] = json::array({material});
    json attrs = {{"POSITION", w.floats(kQuad, "VEC3")},
                  {"TEXCOORD_0", w.floats({0, 1, 1, 1, 1, 0, 0, 0}, "VEC2")}};
    if (uv1) attrs["TEXCOORD_1"] = w.floats({9, 9, 9, 9, 9, 9, 9, 9}, "VEC2");
    w.node({{"mesh", w.mesh(attrs, w.indices(std::vector<uint16_t>{0, 1, 2, 0, 2, 3}), 0)}});
    file = dir.write("mat.gltf", w.text());
    return load_gltf(file);
  }
  ScratchDir dir;
  std::filesystem::path file;
};

// KHR_materials_sheen and _clearcoat: factors (clamped to 0..1) and textures, one with its
// own KHR_texture_transform (an extension's textureInfo is JSON that tinygltf leaves unparsed).
TEST_F(GltfMaterials, SheenAndClearcoatFactorsAndTexturesAreRead) {
  const json transform = {{"KHR_texture_transform", {{"offset", {0.5, 0}}}}};
  const LoadedModel m = load({{"name", "layers"},
                              {"extensions",
                               {{"KHR_materials_sheen",
                                 {{"sheenColorFactor", {0.5, 2, -1}},
                                  {"sheenRoughnessFactor", 0.25},
                                  {"sheenColorTexture", {{"index", 1}}},
                                  {"sheenRoughnessTexture", {{"index", 1}}}}},
                                {"KHR_materials_clearcoat",
                                 {{"clearcoatFactor", 0.75},
                                  {"clearcoatRoughnessFactor", 0.5},
                                  {"clearcoatTexture", {{"index", 0}, {"extensions", transform}}},
                                  {"clearcoatNormalTexture", {{"index", 1}, {"scale", 0.5}}}}}}}},
                             "quadrants.png");
  ASSERT_EQ(m.materials.size(), 1u);
  const auto& mat = test::material_as<MetallicRoughnessMaterial>(*m.materials[0]);
  EXPECT_EQ(mat.sheen_color.x, 0.5);
  EXPECT_EQ(mat.sheen_color.y, 1);
  EXPECT_EQ(mat.sheen_color.z, 0);
  EXPECT_EQ(mat.sheen_roughness, 0.25);
  EXPECT_EQ(mat.sheen_color_texture.kind, Texture::Kind::Image);
  EXPECT_EQ(mat.sheen_roughness_texture.kind, Texture::Kind::Image);
  EXPECT_EQ(mat.clearcoat, 0.75);
  EXPECT_EQ(mat.clearcoat_roughness, 0.5);
  ASSERT_EQ(mat.clearcoat_texture.kind, Texture::Kind::Image);
  EXPECT_EQ(mat.clearcoat_texture.uv_transform.m[0][2], 0.5);
  EXPECT_TRUE(mat.has_clearcoat_normal);
  EXPECT_EQ(mat.clearcoat_normal_scale, 0.5);
  EXPECT_TRUE(mat.textured());
  EXPECT_FALSE(test::has_warning(m, "KHR_materials")) << test::all_warnings(m);
}

// The shading point at uv on the test quad (z = 0, facing +z).
ShadingPoint point_at(Vec2 uv) {
  ShadingPoint sp{{uv.x, 1 - uv.y, 0}, {0, 0, 1}, {0, 0, 1}, {1, 0, 0}, {0, -1, 0}, {}};
  sp.tex.uv = uv;
  return sp;
}

// KHR_materials_specular's textures: F0 = min(F0(ior) x colour factor x colour texture (sRGB),
// 1) x factor x the specular texture's alpha. Red at the top left, green at the top right
// (quadrants.png); grey128.png's alpha is 128/255.
TEST_F(GltfMaterials, SpecularTexturesScaleTheDielectricF0) {
  const json transform = {{"KHR_texture_transform", {{"offset", {0.5, 0}}}}};
  {
    const LoadedModel m =
        load({{"extensions",
               {{"KHR_materials_specular",
                 {{"specularColorFactor", {2, 1, 1}},
                  {"specularColorTexture", {{"index", 0}, {"extensions", transform}}}}}}}},
             "quadrants.png");
    const auto& mat = test::material_as<MetallicRoughnessMaterial>(*m.materials.at(0));
    EXPECT_TRUE(mat.textured());
    const double f0 = 0.2 * 0.2;  // ior 1.5
    // The top left reads the top right's green through the offset, the bottom left the bottom
    // right's white.
    const Color tl = mat.dielectric_f0(point_at({0.25, 0.25}));
    EXPECT_NEAR(tl.x, 0, 1e-12) << str(tl);
    EXPECT_NEAR(tl.y, f0, 1e-12) << str(tl);
    EXPECT_NEAR(tl.z, 0, 1e-12) << str(tl);
    const Color bl = mat.dielectric_f0(point_at({0.25, 0.75}));  // the factor alone
    EXPECT_NEAR(bl.x, 2 * f0, 1e-12) << str(bl);
    EXPECT_NEAR(bl.y, f0, 1e-12) << str(bl);
  }
  {
    const LoadedModel m =
        load({{"extensions",
               {{"KHR_materials_specular",
                 {{"specularFactor", 0.5}, {"specularTexture", {{"index", 0}}}}}}}},
             "grey128.png");
    const auto& mat = test::material_as<MetallicRoughnessMaterial>(*m.materials.at(0));
    const Color c = mat.dielectric_f0(point_at({0.5, 0.5}));
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(c[k], 0.04 * 0.5 * 128.0 / 255.0, 1e-7) << str(c);
  }
}

// transmissionTexture's R scales the factor; thicknessTexture's G = 0 makes the point a thin
// wall, elsewhere the solid refracts.
TEST_F(GltfMaterials, TransmissionAndThicknessTexturesAreRead) {
  const LoadedModel m =
      load({{"pbrMetallicRoughness", {{"metallicFactor", 0}}},
            {"extensions",
             {{"KHR_materials_transmission",
               {{"transmissionFactor", 0.75}, {"transmissionTexture", {{"index", 0}}}}},
              {"KHR_materials_volume",
               {{"thicknessFactor", 2}, {"thicknessTexture", {{"index", 0}}}}}}}},
           "quadrants.png");
  const auto& mat = test::material_as<MetallicRoughnessMaterial>(*m.materials.at(0));
  EXPECT_TRUE(mat.textured());
  EXPECT_FALSE(mat.thin);
  const Vec3 wo{0, 0, 1};
  const Bsdf red = mat.bsdf(point_at({0.25, 0.25}), wo);  // R 1, G 0
  EXPECT_DOUBLE_EQ(red.transmission, 0.75);
  EXPECT_TRUE(red.thin) << "thickness 2 x G 0";
  EXPECT_EQ(red.diffuse, Color(0.25, 0.25, 0.25)) << str(red.diffuse);
  const Bsdf green = mat.bsdf(point_at({0.75, 0.25}), wo);  // R 0, G 1
  EXPECT_DOUBLE_EQ(green.transmission, 0);
  EXPECT_EQ(green.diffuse, Color(1, 1, 1)) << "all opaque: the (white) base is diffuse";
  const Bsdf white = mat.bsdf(point_at({0.75, 0.75}), wo);  // R 1, G 1
  EXPECT_DOUBLE_EQ(white.transmission, 0.75);
  EXPECT_FALSE(white.thin);
  EXPECT_FALSE(test::has_warning(m, "KHR_materials")) << test::all_warnings(m);
}

TEST_F(GltfMaterials, BaseColorTextureTimesFactorWithSamplerAndTopLeftOrigin) {
  const LoadedModel m = load({{"name", "tex"},
                              {"pbrMetallicRoughness",
                               {{"baseColorFactor", {0.5, 1, 1, 1}},
                                {"baseColorTexture", {{"index", 0}}},
                                {"metallicFactor", 0.25},
                                {"roughnessFactor", 0.75}}}},
                             "quadrants.png");
  ASSERT_EQ(m.materials.size(), 1u);
  const Material& mat = *m.materials[0];
  EXPECT_EQ(mat.type(), MetallicRoughnessMaterial::kType);
  ASSERT_EQ(mat.base_color.kind, Texture::Kind::Image);
  EXPECT_EQ(mat.base_color.wrap_s, Wrap::Clamp);
  EXPECT_EQ(mat.base_color.wrap_t, Wrap::Mirror);
  EXPECT_TRUE(mat.base_color.nearest);
  EXPECT_DOUBLE_EQ(test::material_as<MetallicRoughnessMaterial>(mat).metallic, 0.25);
  EXPECT_DOUBLE_EQ(test::material_as<MetallicRoughnessMaterial>(mat).roughness, 0.75);
  EXPECT_FALSE(mat.double_sided);  // glTF default
  // uv (0,0) is the image's top-left: red, scaled by the factor's 0.5.
  const Color tl = texel(mat.base_color, {0.25, 0.25});
  const Color br = texel(mat.base_color, {0.75, 0.75});
  EXPECT_EQ(tl, Color(0.5, 0, 0)) << str(tl);
  EXPECT_EQ(br, Color(0.5, 1, 1)) << str(br);
  // uvs are stored as given: vertex 3 at (0,1,0) has uv (0,0).
  const TriangleMesh& tm = m.prototypes.at(0).meshes.at(0);
  EXPECT_EQ(tm.uvs.at(3), Vec2f(0, 0));
}

TEST_F(GltfMaterials, ColourTexturesAreSrgbDecodedDataTexturesStayLinear) {
  const LoadedModel m =
      load({{"pbrMetallicRoughness",
             {{"baseColorTexture", {{"index", 1}}}, {"metallicRoughnessTexture", {{"index", 1}}}}},
            {"normalTexture", {{"index", 1}, {"scale", 0.5}}},
            {"emissiveTexture", {{"index", 1}}},
            {"emissiveFactor", {1, 0.5, 0.25}},
            {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4}}}}}},
           "grey128.png");
  const Material& mat = *m.materials.at(0);
  const double lin = 128.0 / 255.0, srgb = srgb_to_linear(float(lin));
  EXPECT_NEAR(texel(mat.base_color, {0.5, 0.5}).x, srgb, 1e-6);
  EXPECT_NEAR(
      texel(test::material_as<MetallicRoughnessMaterial>(mat).metallic_roughness, {0.5, 0.5}).y,
      lin, 1e-6);
  EXPECT_TRUE(mat.has_normal_map);
  EXPECT_DOUBLE_EQ(mat.normal_scale, 0.5);
  EXPECT_NEAR(texel(mat.normal_map, {0.5, 0.5}).z, lin, 1e-6);
  const Color e = texel(mat.emission, {0.5, 0.5});
  EXPECT_NEAR(e.y, 0.5 * srgb, 1e-6) << str(e);
  EXPECT_DOUBLE_EQ(mat.emission_strength, 4);
  EXPECT_TRUE(mat.is_emissive());
  // Opaque: the texture's alpha is ignored by the material, but the texture keeps it.
  double a = 0;
  texel(mat.base_color, {0.5, 0.5}, &a);
  EXPECT_NEAR(a, lin, 1e-6);
}

TEST_F(GltfMaterials, AlphaModes) {
  {
    const LoadedModel m = load({{"alphaMode", "MASK"},
                                {"alphaCutoff", 0.3},
                                {"doubleSided", true},
                                {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 0.25}}}}},
                               "quadrants.png");
    const Material& mat = *m.materials.at(0);
    EXPECT_EQ(mat.alpha_mode, Material::AlphaMode::Mask);
    EXPECT_DOUBLE_EQ(mat.alpha_cutoff, 0.3);
    EXPECT_TRUE(mat.double_sided);
    // The factor's alpha reaches the lookup even without a texture.
    double a = 0;
    texel(mat.base_color, {0.5, 0.5}, &a);
    EXPECT_FLOAT_EQ(float(a), 0.25f);
  }
  {
    const LoadedModel m =
        load({{"name", "glass"},
              {"alphaMode", "BLEND"},
              {"pbrMetallicRoughness",
               {{"baseColorTexture", {{"index", 0}}}, {"baseColorFactor", {1, 1, 1, 0.5}}}}},
             "grey128.png");
    const Material& mat = *m.materials.at(0);
    // BLEND is transparency (the BSDF's opacity, tests/render/gltf_materials_test.cpp), not a
    // cut-out, and no longer warned about.
    EXPECT_EQ(mat.alpha_mode, Material::AlphaMode::Blend);
    EXPECT_FALSE(mat.alpha_masked());
    EXPECT_TRUE(m.warnings.empty()) << test::all_warnings(m);
    double a = 0;
    texel(mat.base_color, {0.5, 0.5}, &a);
    EXPECT_NEAR(a, 0.5 * 128 / 255.0, 1e-6);  // texture alpha x factor alpha
  }
}

TEST_F(GltfMaterials, TextureTransformAndTexCoordOverride) {
  const LoadedModel m =
      load({{"pbrMetallicRoughness",
             {{"baseColorTexture",
               {{"index", 0},
                {"texCoord", 1},
                {"extensions",
                 {{"KHR_texture_transform",
                   {{"offset", {0.5, 0}}, {"scale", {0.5, 0.5}}, {"texCoord", 0}}}}}}}}}},
           "quadrants.png", /*uv1=*/true);
  const Material& mat = *m.materials.at(0);
  EXPECT_FALSE(mat.base_color.uv_transform.identity());
  // uv (0.5, 0.5) -> 0.5 * 0.5 + (0.5, 0) = (0.75, 0.25): the top-right texel, green.
  EXPECT_EQ(texel(mat.base_color, {0.5, 0.5}), Color(0, 1, 0));
  // texCoord 0 from the extension overrides the textureInfo's 1: uvs are TEXCOORD_0, not 9s.
  EXPECT_EQ(m.prototypes.at(0).meshes.at(0).uvs.at(0), Vec2f(0, 1));
}

// The KHR_texture_transform spec's own example: offset (0,1), rotation pi/2, scale 0.5 "utilizes
// only the lower left quadrant of the source image, rotated clockwise 90 degrees". The GLSL
// listing in the spec has the transposed rotation (KhronosGroup/glTF issue 1563); this is the
// convention of the spec text, the sample models and the reference viewers.
TEST(UvTransform, MatchesTheKhrTextureTransformExample) {
  const UvTransform t = UvTransform::from_offset_rotation_scale({0, 1}, kPi / 2, {0.5, 0.5});
  const Vec2 corners[4] = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
  const Vec2 want[4] = {{0, 1}, {0, 0.5}, {0.5, 1}, {0.5, 0.5}};
  for (int i = 0; i < 4; ++i) {
    const Vec2 got = t.apply(corners[i]);
    EXPECT_NEAR(got.x, want[i].x, 1e-12) << "corner " << i << " -> " << got.x << ", " << got.y;
    EXPECT_NEAR(got.y, want[i].y, 1e-12) << "corner " << i << " -> " << got.x << ", " << got.y;
  }
}

TEST(GltfLoader, UnreadableImageFileIsAWarningAndTheFactorRemains) {
  ScratchDir dir;
  GltfWriter w;
  w.j["images"] = {{{"uri", "not%20here.png"}}};
  w.j["textures"] = {{{"source", 0}}};
  w.j["materials"] = {
      {{"pbrMetallicRoughness",
        {{"baseColorTexture", {{"index", 0}}}, {"baseColorFactor", {0.1, 0.2, 0.3, 1}}}}}};
  w.node({{"mesh", w.mesh({{"POSITION", w.floats(kQuad, "VEC3")}}, quad_indices(w), 0)}});
  const LoadedModel m = load_gltf(dir.write("missing_tex.gltf", w.text()));
  const Material& mat = *m.materials.at(0);
  EXPECT_EQ(mat.base_color.kind, Texture::Kind::Constant);
  EXPECT_EQ(mat.base_color.value, Color(0.1, 0.2, 0.3));
  // The URI is percent-decoded before the file is looked for.
  EXPECT_TRUE(test::has_warning(m, "not here.png")) << test::all_warnings(m);
  // Without its image the material is not textured, so the missing TEXCOORD_0 is no concern.
  EXPECT_FALSE(test::has_warning(m, "no TEXCOORD")) << test::all_warnings(m);
}

TEST_F(GltfMaterials, TexturedMaterialWithoutTexcoordsIsWarned) {
  GltfWriter w;
  w.j["images"] = {
      {{"uri", "data:image/png;base64," +
                   test::base64(test::read_bytes(test::data_dir() / "models/quadrants.png"))}}};
  w.j["textures"] = {{{"source", 0}}};
  w.j["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
  w.node(
      {{"mesh", w.mesh({{"POSITION", w.floats(kQuad, "VEC3")}}, quad_indices(w), 0, 4, "bare")}});
  const LoadedModel m = load_gltf(dir.write("nouv.gltf", w.text()));
  EXPECT_TRUE(test::has_warning(m, "mesh 'bare' has a textured material but no TEXCOORD_0"))
      << test::all_warnings(m);
}

TEST(GltfLoader, UnsupportedExtensionsAreWarningsNamingThem) {
  ScratchDir dir;
  GltfWriter w;
  w.node({{"mesh", w.mesh({{"POSITION", w.floats(kQuad, "VEC3")}}, quad_indices(w))}});
  w.j["extensionsUsed"] = {"KHR_materials_anisotropy", "EXT_made_up", "KHR_texture_transform"};
  w.j["extensionsRequired"] = {"EXT_made_up"};
  const LoadedModel m = load_gltf(dir.write("ext.gltf", w.text()));
  EXPECT_TRUE(test::has_warning(m, "KHR_materials_anisotropy is not supported"))
      << test::all_warnings(m);
  EXPECT_TRUE(test::has_warning(m, "required glTF extension EXT_made_up")) << test::all_warnings(m);
  EXPECT_FALSE(test::has_warning(m, "KHR_texture_transform")) << test::all_warnings(m);
}

TEST(GltfLoader, MissingFileIsALoadErrorSayingNoSuchFile) {
  const auto file = std::filesystem::temp_directory_path() / "anamorph_no_such_model.gltf";
  try {
    load_model(file);
    FAIL() << "no LoadError";
  } catch (const LoadError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("cannot open " + file.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find("No such file"), std::string::npos) << msg;
  }
}

TEST(GltfLoader, GarbageFilesAreLoadErrorsNamingTheFile) {
  ScratchDir dir;
  for (const char* name : {"garbage.gltf", "garbage.glb", "truncated.glb"}) {
    std::string bytes = "\x01\x02 this is not a model {{{";
    if (std::string(name) == "truncated.glb") bytes = std::string("glTF\x02\0\0\0", 8) + "xx";
    const auto file = dir.write(name, bytes);
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
