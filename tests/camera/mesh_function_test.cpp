// The mesh origin function: texture-space point location, interpolation, transforms, and
// loading through load_model.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "camera/org_mesh.h"
#include "function_test_util.h"
#include "scene/loaders.h"

namespace anamorph {
namespace {

using test::cat;
using test::expect_close;
using test::sample;
using test::str;

// A grid of (n+1)^2 vertices on a cylinder section x = sin(a), z = -cos(a), y = height, with
// texture coordinates (i/n, j/n) and optional exact normals.
LoadedModel curved_grid(int n, bool normals, Transform world_from_object = {}) {
  TriangleMesh m;
  m.name = "sheet";
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double a = -1 + 2.0 * i / n, y = 1 - 2.0 * j / n;
      m.positions.push_back(Vec3f(Vec3{std::sin(a), y, -std::cos(a)}));
      if (normals) m.normals.push_back(Vec3f(Vec3{-std::sin(a), 0, std::cos(a)}));
      m.uvs.push_back({float(i) / n, float(j) / n});
    }
  const auto id = [&](int i, int j) { return uint32_t(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      for (uint32_t k :
           {id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j), id(i + 1, j + 1), id(i, j + 1)})
        m.indices.push_back(k);
  LoadedModel model;
  model.prototypes.push_back({"proto", {m}});
  model.instances.push_back({0, world_from_object, "node", {}});
  return model;
}

// Brute force: the triangle containing (s, t) in texture space and the interpolated point.
bool brute_force(const LoadedModel& model, Vec2 st, Vec3* p) {
  const TriangleMesh& m = model.prototypes[0].meshes[0];
  for (size_t k = 0; k < m.indices.size(); k += 3) {
    const uint32_t i0 = m.indices[k], i1 = m.indices[k + 1], i2 = m.indices[k + 2];
    const Vec2 a{m.uvs[i0].x, m.uvs[i0].y}, b{m.uvs[i1].x, m.uvs[i1].y},
        c{m.uvs[i2].x, m.uvs[i2].y};
    const double det = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    const double b1 = ((st.x - a.x) * (c.y - a.y) - (st.y - a.y) * (c.x - a.x)) / det;
    const double b2 = ((b.x - a.x) * (st.y - a.y) - (b.y - a.y) * (st.x - a.x)) / det;
    if (b1 < -1e-9 || b2 < -1e-9 || b1 + b2 > 1 + 1e-9) continue;
    const Vec3 p0(m.positions[i0]), p1(m.positions[i1]), p2(m.positions[i2]);
    *p = model.instances[0].world_from_object.point(p0 + (p1 - p0) * b1 + (p2 - p0) * b2);
    return true;
  }
  return false;
}

TEST(MeshOrg, FindsTheTriangleOfEveryTexturePoint) {
  const LoadedModel model = curved_grid(37, true, Transform::translate({1, 2, 3}));
  const auto f = make_mesh_org(model.prototypes, model.instances, "");
  for (int j = 0; j <= 50; ++j)
    for (int i = 0; i <= 50; ++i) {
      const Vec2 uv{i / 50.0, j / 50.0 * 0.999 + 0.0003};
      Vec3 expected;
      ASSERT_TRUE(brute_force(model, uv, &expected));
      expect_close(sample(*f, uv).p, expected, 1e-6, cat("p at ", uv.x, ", ", uv.y));
    }
}

TEST(MeshOrg, InterpolatesPositionAndNormalWithExactDerivatives) {
  const LoadedModel model = curved_grid(8, true);
  const auto f = make_mesh_org(model.prototypes, model.instances, "", {0.1, 0.9}, {0.9, 0.05});
  // Points inside triangles (derivatives jump across edges).
  for (const Vec2 uv : {Vec2{0.3, 0.35}, Vec2{0.61, 0.72}, Vec2{0.83, 0.2}}) {
    test::expect_derivatives_match(*f, uv, 1e-6, 1e-7);
    const SurfaceSample s = sample(*f, uv);
    EXPECT_NEAR(length(s.n), 1, 1e-12);
    // The vertex normals point toward the cylinder's axis; so does their interpolation.
    EXPECT_GT(dot(s.n, Vec3{-s.p.x, 0, -s.p.z}), 0.99) << str(s.n) << " at " << str(s.p);
  }
}

TEST(MeshOrg, FlatMeshUsesGeometricNormal) {
  const LoadedModel model = curved_grid(4, false);
  const auto f = make_mesh_org(model.prototypes, model.instances, "");
  const SurfaceSample s = sample(*f, {0.3, 0.4});
  test::expect_normal_valid(*f, {0.3, 0.4}, 1e-6);
  // The geometric normal is the counterclockwise side: these triangles run right, then down as
  // seen from the axis, which is clockwise from there, so it points away from the axis.
  EXPECT_GT(dot(s.n, Vec3{s.p.x, 0, s.p.z}), 0.9) << str(s.n);
  const auto g = make_mesh_org(model.prototypes, model.instances, "", {}, {}, true);
  expect_close(sample(*g, {0.3, 0.4}).n, -s.n, 0, "flip_normal");
}

TEST(MeshOrg, OutsideEveryTriangleIsNoRay) {
  const LoadedModel model = curved_grid(4, true);
  const auto f = make_mesh_org(model.prototypes, model.instances, "", {-0.5, 1.5}, {0, 1});
  SurfaceSample s;
  EXPECT_FALSE(f->eval({0.1, 0.5}, &s)) << "u' = -0.3 lies outside the UV layout";
  EXPECT_TRUE(f->eval({0.5, 0.5}, &s));
  const double us[] = {0.1, 0.5}, vs[] = {0.5, 0.5};
  SurfaceBatch b;
  f->eval_batch(us, vs, 2, &b);
  EXPECT_FALSE(b.ok[0]) << "eval_batch marks no ray";
  EXPECT_EQ(b.p[0][0], 0.0) << "a lane without ray is all zero";
  EXPECT_TRUE(b.ok[1]);
}

TEST(MeshOrg, SelectByName) {
  const LoadedModel model = curved_grid(4, true);
  EXPECT_NO_THROW(make_mesh_org(model.prototypes, model.instances, "sheet"));
  EXPECT_NO_THROW(make_mesh_org(model.prototypes, model.instances, "node"));
  try {
    make_mesh_org(model.prototypes, model.instances, "nothing");
    FAIL() << "expected ParamError";
  } catch (const ParamError& e) {
    EXPECT_EQ(e.key, "select");
  }
}

TEST(MeshOrg, NoTextureCoordinatesIsAnError) {
  LoadedModel model = curved_grid(2, true);
  model.prototypes[0].meshes[0].uvs.clear();
  try {
    make_mesh_org(model.prototypes, model.instances, "");
    FAIL() << "expected ParamError";
  } catch (const ParamError& e) {
    EXPECT_EQ(e.key, "file");
    EXPECT_NE(std::string(e.what()).find("texture coordinates"), std::string::npos) << e.what();
  }
}

TEST(MeshOrg, LoadsAFileThroughTheRegistry) {
  // An OBJ quad: texture v grows upward in OBJ, so vt (0, 0) is the image's bottom-left.
  const auto path = std::filesystem::temp_directory_path() / "anamorph_mesh_org_test.obj";
  {
    std::ofstream o(path);
    o << "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n"
         "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
         "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";
  }
  const auto f = make_org("mesh", cat("file = \"", path.string(), "\""));
  expect_close(sample(*f, {0, 1}).p, {-1, -1, 0}, 1e-6, "bottom-left");
  expect_close(sample(*f, {1, 0}).p, {1, 1, 0}, 1e-6, "top-right");
  expect_close(sample(*f, {0.25, 0.5}).p, {-0.5, 0, 0}, 1e-6, "inside");
  expect_close(sample(*f, {0.25, 0.5}).n, {0, 0, 1}, 1e-6, "counterclockwise faces +z");
  std::filesystem::remove(path);
  try {
    make_org("mesh", "file = \"/nonexistent/anamorph/missing.obj\"");
    FAIL() << "expected ParamError";
  } catch (const ParamError& e) {
    EXPECT_EQ(e.key, "file");
  }
}

}  // namespace
}  // namespace anamorph
