// Exact analytic intersections through the whole Embree path.
#include <gtest/gtest.h>

#include <cmath>

#include "accel/accel.h"
#include "accel/shapes.h"
#include "scene/scene_loader.h"
#include "test_util.h"

namespace anamorph {

namespace {
struct Probe {
  Scene scene;
  std::unique_ptr<Accel> accel;
  explicit Probe(const std::string& objects) : scene(load_scene_from_string(objects, "t.toml")) {
    accel = std::make_unique<Accel>(scene);
  }
  Hit hit(Vec3 o, Vec3 d) {
    Hit h;
    EXPECT_TRUE(accel->intersect({o, normalize(d)}, &h)) << "expected a hit";
    return h;
  }
};
void expect_vec(const Vec3& a, const Vec3& b, double tol, const char* what) {
  EXPECT_NEAR(length(a - b), 0, tol) << what << ": got (" << a.x << ", " << a.y << ", " << a.z
                                     << ") want (" << b.x << ", " << b.y << ", " << b.z << ")";
}
}  // namespace

TEST(Shapes, SphereHitPointAndNormal) {
  Probe p("[[object]]\ntype = \"sphere\"\ncenter = [1, 2, 3]\nradius = 2\n");
  const Hit h = p.hit({1, 2, 13}, {0, 0, -1});
  EXPECT_NEAR(h.t, 8, 1e-5);
  expect_vec(h.p, {1, 2, 5}, 1e-5, "point");
  expect_vec(h.ng, {0, 0, 1}, 1e-9, "normal");
  // Oblique: |p - c| = r exactly (recomputed in double precision).
  const Hit h2 = p.hit({-5, 1, 2}, {1, 0.3, 0.2});
  EXPECT_NEAR(length(h2.p - Vec3{1, 2, 3}), 2, 1e-6);
  EXPECT_NEAR(dot(h2.ng, normalize(h2.p - Vec3{1, 2, 3})), 1, 1e-9);
}

TEST(Shapes, SphereFromInsideHitsFarSide) {
  Probe p("[[object]]\ntype = \"sphere\"\nradius = 1\n");
  const Hit h = p.hit({0, 0, 0}, {0, 1, 0});
  EXPECT_NEAR(h.t, 1, 1e-6);
}

TEST(Shapes, PlaneBoxCylinderDisk) {
  Probe plane("[[object]]\ntype = \"plane\"\npoint = [0, -1, 0]\nnormal = [0, 1, 0]\n");
  EXPECT_NEAR(plane.hit({0.3, 4, 0.2}, {0, -1, 0}).t, 5, 1e-5);
  Probe box("[[object]]\ntype = \"box\"\nmin = [-1, -2, -3]\nmax = [1, 2, 3]\n");
  const Hit hb = box.hit({10, 0.5, 0.5}, {-1, 0, 0});
  EXPECT_NEAR(hb.t, 9, 1e-5);
  expect_vec(hb.ng, {1, 0, 0}, 1e-12, "box normal");
  Probe cyl("[[object]]\ntype = \"cylinder\"\nbase = [0, 0, 0]\ntop = [0, 2, 0]\nradius = 0.5\n");
  const Hit hc = cyl.hit({0, 1, 5}, {0, 0, -1});
  EXPECT_NEAR(hc.t, 4.5, 1e-5);
  expect_vec(hc.ng, {0, 0, 1}, 1e-9, "cylinder side normal");
  const Hit hcap = cyl.hit({0.1, 5, 0}, {0, -1, 0});
  EXPECT_NEAR(hcap.t, 3, 1e-5);
  expect_vec(hcap.ng, {0, 1, 0}, 1e-9, "cylinder cap normal");
  Probe disk("[[object]]\ntype = \"disk\"\ncenter = [0, 0, -2]\nnormal = [0, 0, 1]\nradius = 1\n");
  EXPECT_NEAR(disk.hit({0.5, 0.5, 0}, {0, 0, -1}).t, 2, 1e-5);
  Hit miss;
  EXPECT_FALSE(disk.accel->intersect({{1.2, 0, 0}, {0, 0, -1}}, &miss))
      << "outside the disk radius";
}

TEST(Shapes, RectangleIsAFinitePlanePatch) {
  // A 2 x 1 patch in the plane z = -2 facing +z (edge_u x edge_v = x * y = +z), and a
  // parallelogram.
  Probe r(
      "[[object]]\ntype = \"rectangle\"\ncenter = [0, 0, -2]\nedge_u = [2, 0, 0]\n"
      "edge_v = [0, 1, 0]\n");
  const Hit h = r.hit({0.9, 0.4, 0}, {0, 0, -1});
  EXPECT_NEAR(h.t, 2, 1e-5);
  expect_vec(h.ng, {0, 0, 1}, 1e-12, "rectangle normal");
  expect_vec(h.dpdu, {2, 0, 0}, 1e-12, "dpdu = edge_u");
  expect_vec(h.dpdv, {0, 1, 0}, 1e-12, "dpdv = edge_v");
  EXPECT_NEAR(h.uv.x, 0.95, 1e-6) << "u runs along edge_u";
  EXPECT_NEAR(h.uv.y, 0.9, 1e-6) << "v runs along edge_v";
  Hit miss;
  EXPECT_FALSE(r.accel->intersect({{1.1, 0, 0}, {0, 0, -1}}, &miss)) << "beyond edge_u";
  EXPECT_FALSE(r.accel->intersect({{0, 0.6, 0}, {0, 0, -1}}, &miss)) << "beyond edge_v";
  Probe par("[[object]]\ntype = \"rectangle\"\nedge_u = [1, 0, 0]\nedge_v = [1, 0, -1]\n");
  EXPECT_NEAR(par.hit({0.9, 1, -0.45}, {0, -1, 0}).t, 1, 1e-5) << "inside the slanted side";
  EXPECT_FALSE(par.accel->intersect({{-0.9, 1, -0.45}, {0, -1, 0}}, &miss))
      << "outside the parallelogram, inside its bounding square";
}

TEST(Shapes, TiltedCylinderFollowsItsAxis) {
  Probe p(
      "[[object]]\ntype = \"cylinder\"\nbase = [-1, 1, 1]\ntop = [1, -1, -1]\nradius = "
      "0.25\ncapped = false\n");
  const Vec3 axis = normalize(Vec3{2, -2, -2});
  const Hit h = p.hit({5, 5, 0}, Vec3{0, 0, 0} - Vec3{5, 5, 0});
  const Vec3 rel = h.p - Vec3{-1, 1, 1};
  const double dist = length(rel - axis * dot(rel, axis));
  EXPECT_NEAR(dist, 0.25, 1e-6);
}

TEST(Shapes, SurfaceDerivativesMatchFiniteDifferences) {
  AnalyticShape s;
  s.kind = AnalyticShape::Kind::Sphere;
  s.radius = 1.5;
  // Move along dpdu on the surface: the uv parameterization changes by the unit step.
  const Vec3 p = normalize(Vec3{0.3, 0.5, 0.8}) * 1.5;
  const ShapeSurface ss = shape_surface(s, p);
  const double h = 1e-6;
  const ShapeSurface s2 = shape_surface(s, normalize(p + ss.dpdu * h) * 1.5);
  EXPECT_NEAR(s2.uv.x - ss.uv.x, h, 1e-9);
  EXPECT_NEAR(s2.uv.y - ss.uv.y, 0, 1e-9);
}

// Shadow rays through glass (Whitted): the opaque query ignores see-through objects, the
// see-through query finds only them, for shapes, meshes moved to world space and instanced
// meshes alike; a scene without see-through objects has no see-through structure.
TEST(Shapes, OpaqueAndSeeThroughQueriesSeeTheirOwnObjects) {
  const std::string quad = (test::data_dir() / "models" / "textured_quad.obj").string();
  const std::string gltf = (test::data_dir() / "models" / "shared_mesh.gltf").string();
  const Scene scene = load_scene_from_string(
      "[[material]]\nname = \"glass\"\ntransmission = 0.5\n"
      "[[object]]\ntype = \"sphere\"\ncenter = [0, 0, -5]\nradius = 1\nmaterial = \"glass\"\n"
      "[[object]]\ntype = \"box\"\nmin = [-1, -1, -9]\nmax = [1, 1, -8]\n"
      "[[object]]\ntype = \"mesh\"\nfile = \"" +
          quad +
          "\"\nmaterial = \"glass\"\n"
          "transform = { translate = [9.5, -0.5, -3] }\n"
          "[[object]]\ntype = \"mesh\"\nfile = \"" +
          gltf +
          "\"\nmaterial = \"glass\"\n"
          "transform = { translate = [-20, 0, -6] }\n",
      "t.toml");
  const Accel accel(scene);
  ASSERT_TRUE(accel.has_see_through());
  const auto ray = [](Vec3 o, Vec3 d) { return Ray{o, normalize(d), 0, kInf}; };
  // Through the glass sphere to the box behind it.
  const Ray through = ray({0, 0, 0}, {0, 0, -1});
  Hit h;
  ASSERT_TRUE(accel.intersect(through, &h));
  EXPECT_NEAR(h.t, 4, 1e-5) << "the full query meets the sphere first";
  EXPECT_TRUE(accel.occluded_by_opaque(through)) << "the box blocks";
  EXPECT_TRUE(accel.occluded(through));
  ASSERT_TRUE(accel.intersect_see_through(through, &h));
  EXPECT_NEAR(h.t, 4, 1e-5);
  EXPECT_EQ(scene.materials[h.material]->shadow_transmission(), 0.5);
  // Glass alone: not blocked, and the see-through query meets it.
  for (const Vec3 target : {Vec3{10, 0, -3}, Vec3{-17.5, 0.5, -6}, Vec3{-19, 4, -6}}) {
    const Ray r = ray({target.x, target.y, 5}, {0, 0, -1});
    Hit any;
    ASSERT_TRUE(accel.intersect(r, &any)) << target.x;
    EXPECT_FALSE(accel.occluded_by_opaque(r)) << "glass at x = " << target.x << " blocked";
    EXPECT_TRUE(accel.occluded(r)) << target.x;
    Hit g;
    ASSERT_TRUE(accel.intersect_see_through(r, &g)) << target.x;
    EXPECT_NEAR(g.t, any.t, 1e-6) << target.x;
    EXPECT_EQ(g.object_id, any.object_id) << "the same record: " << target.x;
  }
  // Beside everything: nothing anywhere.
  const Ray miss = ray({0, 30, 0}, {0, 0, -1});
  EXPECT_FALSE(accel.occluded_by_opaque(miss));
  EXPECT_FALSE(accel.intersect_see_through(miss, &h));
  // Without glass there is no see-through structure, and nothing is see-through.
  const Scene opaque = load_scene_from_string(
      "[[object]]\ntype = \"sphere\"\ncenter = [0, 0, -5]\nradius = 1\n", "t.toml");
  const Accel solid(opaque);
  EXPECT_FALSE(solid.has_see_through());
  EXPECT_TRUE(solid.occluded_by_opaque(through));
  EXPECT_FALSE(solid.intersect_see_through(through, &h));
}

// Infinite planes are tested beside the BVH: every query (nearest, any-hit, packets, the
// see-through walk) still finds them, and what lies before them still comes first.
TEST(Shapes, InfinitePlanesAreFoundBesideTheBvh) {
  const Scene scene = load_scene_from_string(
      "[[material]]\nname = \"glass\"\ntransmission = 0.5\n"
      "[[object]]\ntype = \"plane\"\n"
      "[[object]]\ntype = \"plane\"\npoint = [0, 5, 0]\nnormal = [0, -1, 0]\nmaterial = \"glass\"\n"
      "[[object]]\ntype = \"box\"\nmin = [-1, 0, -1]\nmax = [1, 1, 1]\n",
      "t.toml");
  const Accel accel(scene);
  EXPECT_TRUE(accel.has_see_through());
  EXPECT_GE(accel.bounds().hi.x, 1e5) << "the planes' square is in the bounds";
  const auto down = [](double x) { return Ray{{x, 3, 0}, {0, -1, 0}, 0, kInf}; };
  Hit h;
  ASSERT_TRUE(accel.intersect(down(0), &h));
  EXPECT_NEAR(h.t, 2, 1e-6) << "the box's top before the floor";
  ASSERT_TRUE(accel.intersect(down(5), &h));
  EXPECT_NEAR(h.t, 3, 1e-6) << "the floor";
  EXPECT_EQ(h.object_id, 0u);
  EXPECT_NEAR(h.ng.y, 1, 1e-12);
  EXPECT_TRUE(accel.occluded(down(5)));
  EXPECT_TRUE(accel.occluded_by_opaque(down(5)));
  EXPECT_FALSE(accel.occluded(Ray{{5, 3, 0}, {0, -1, 0}, 0, 2.5})) << "short of the floor";
  // Up: only the glass ceiling.
  const Ray up{{5, 3, 0}, {0, 1, 0}, 0, kInf};
  ASSERT_TRUE(accel.intersect(up, &h));
  EXPECT_NEAR(h.t, 2, 1e-6);
  EXPECT_EQ(h.object_id, 1u);
  EXPECT_TRUE(accel.occluded(up));
  EXPECT_FALSE(accel.occluded_by_opaque(up));
  EXPECT_TRUE(accel.near_see_through(up));
  ASSERT_TRUE(accel.intersect_see_through(up, &h));
  EXPECT_EQ(h.object_id, 1u);
  // A packet: the same hits as one ray at a time.
  double org[3][16], dir[3][16];
  bool valid[16], found[16];
  Hit hits[16];
  for (int i = 0; i < 16; ++i) {
    const Ray r = i % 3 == 2 ? up : down(i * 0.4 - 3);
    for (int c = 0; c < 3; ++c) org[c][i] = r.o[c], dir[c][i] = r.d[c];
    valid[i] = i != 7;
  }
  accel.intersect16(org, dir, valid, hits, found);
  for (int i = 0; i < 16; ++i) {
    const Ray r = i % 3 == 2 ? up : down(i * 0.4 - 3);
    Hit one;
    const bool hit_one = accel.intersect(r, &one);
    if (!valid[i]) {
      EXPECT_FALSE(found[i]);
      continue;
    }
    ASSERT_EQ(found[i], hit_one) << "lane " << i;
    EXPECT_EQ(hits[i].object_id, one.object_id) << "lane " << i;
    EXPECT_EQ(hits[i].t, one.t) << "lane " << i;
  }
}

}  // namespace anamorph
