// Object motion blur from glTF animation (issue 34, part 4): each ray sees the objects where they
// are at its time in the shutter. Against closed forms:
//   an unlit white strip 0.1 wide crossing 0.4 during the shutter (moved by its node, or by a
//   morph target): every point it passes is covered a quarter of the shutter, so every pixel
//   averages 1/4;
//   rays at given times meet a translating, a rotating and a deforming mesh where they are then,
//   instanced or flattened into the top level.
// And the same bits for any thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "accel/accel.h"
#include "material/material_kinds.h"
#include "render_util.h"
#include "scene/loader_fixture.h"

namespace anamorph {
namespace {

using Json = nlohmann::json;

// A white unlit strip x in [-0.05, 0.05] (20 m tall) at z = -1, moving from x - 0.2 at time 0 to
// x + 0.2 at 1/24 s (frames 0 and 1 at 24 fps): by its node's translation, or (`morph`) by a
// morph target whose weight goes from 0 to 1 while the node stays at x - 0.2.
std::filesystem::path write_strip(const test::ScratchDir& dir, bool morph) {
  test::GltfWriter w;
  const int pos =
      w.floats({-0.05f, -10, -1, 0.05f, -10, -1, 0.05f, 10, -1, -0.05f, 10, -1}, "VEC3");
  const int idx = w.indices(std::vector<uint16_t>{0, 1, 2, 0, 2, 3});
  w.j["materials"] = {{{"name", "white"},
                       {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}}},
                       {"extensions", {{"KHR_materials_unlit", Json::object()}}}}};
  w.j["extensionsUsed"] = {"KHR_materials_unlit"};
  const int mesh = w.mesh({{"POSITION", pos}}, idx, 0, 4, "strip");
  const int times = w.floats({0, 1.0f / 24}, "SCALAR");
  int out;
  std::string path;
  if (morph) {
    w.j["meshes"][size_t(mesh)]["primitives"][0]["targets"] = {
        {{"POSITION", w.floats({0.4f, 0, 0, 0.4f, 0, 0, 0.4f, 0, 0, 0.4f, 0, 0}, "VEC3")}}};
    w.j["meshes"][size_t(mesh)]["weights"] = {0};
    out = w.floats({0, 1}, "SCALAR");
    path = "weights";
  } else {
    out = w.floats({-0.2f, 0, 0, 0.2f, 0, 0}, "VEC3");
    path = "translation";
  }
  w.node({{"mesh", mesh}, {"translation", {-0.2, 0, 0}}});
  const Json sampler = {{"input", times}, {"output", out}};
  const Json channel = {{"sampler", 0}, {"target", {{"node", 0}, {"path", path}}}};
  w.j["animations"] =
      Json::array({{{"samplers", Json::array({sampler})}, {"channels", Json::array({channel})}}});
  return dir.write("strip.gltf", w.text());
}

// The strip seen head-on (every pixel's rays meet z = -1 within |x| < 0.13), frame 0 with the
// shutter [0, 1] frames.
std::string strip_scene(const std::filesystem::path& file, int spp) {
  return "[image]\nwidth = 16\nheight = 16\n[render]\nintegrator = \"path\"\nspp = " +
         std::to_string(spp) +
         "\n[camera]\nfov = 10\nlook_from = [0, 0, 0]\nlook_at = [0, 0, -1]\nshutter = [0, "
         "1]\n[[object]]\ntype = \"mesh\"\nfile = \"" +
         file.string() + "\"\n";
}

double mean(const Film& f, int x0, int x1) {
  double sum = 0;
  for (int y = 0; y < f.height(); ++y)
    for (int x = x0; x < x1; ++x) sum += f.pixel(x, y).x;
  return sum / double((x1 - x0) * f.height());
}

// Each sample is 1 with probability 1/4 (its time in the covered quarter): 64 x 128 samples per
// half image, standard error 0.0048 (less: the times are stratified); 0.02 is 4 of them.
void expect_quarter_covered(bool morph) {
  const test::ScratchDir dir;
  const test::Rendered r = test::render_text(strip_scene(write_strip(dir, morph), 64));
  const double left = mean(*r.film, 0, 8), right = mean(*r.film, 8, 16);
  EXPECT_NEAR(left, 0.25, 0.02) << (morph ? "morph" : "translation");
  EXPECT_NEAR(right, 0.25, 0.02) << (morph ? "morph" : "translation");
}

TEST(MotionBlur, TranslatingStripCoversEachPixelAQuarterOfTheShutter) {
  expect_quarter_covered(false);
}

TEST(MotionBlur, MorphingStripCoversEachPixelAQuarterOfTheShutter) { expect_quarter_covered(true); }

// A closed shutter: the still at frame 0 (the strip at x - 0.2, out of view: black), and the
// accel has no time steps.
TEST(MotionBlur, ClosedShutterRendersTheStill) {
  const test::ScratchDir dir;
  const test::Rendered r =
      test::render_text(strip_scene(write_strip(dir, false), 4), {"camera.shutter=[0, 0]"});
  EXPECT_EQ(mean(*r.film, 0, 16), 0);
  EXPECT_TRUE(r.scene.instances[0].motion.empty());
}

TEST(MotionBlur, SameBitsForAnyThreadCount) {
  const test::ScratchDir dir;
  const std::string scene = strip_scene(write_strip(dir, true), 8);
  const test::Rendered a = test::render_text(scene, {}, 1);
  const test::Rendered b = test::render_text(scene, {}, 3);
  const test::Rendered c = test::render_text(scene, {"render.tile_size=4"}, 2);
  int differ = 0;
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) {
      const Color p = a.film->pixel(x, y);
      differ += !(p == b.film->pixel(x, y)) + !(p == c.film->pixel(x, y));
    }
  EXPECT_EQ(differ, 0);
  EXPECT_GT(mean(*a.film, 0, 16), 0.1);  // (blurred: something to compare)
}

// Scenes built in code: a unit quad (x, y in [-0.5, 0.5], z = 0) in prototypes, rays down -z.
TriangleMesh unit_quad() {
  TriangleMesh m;
  m.positions = {{-0.5f, -0.5f, 0}, {0.5f, -0.5f, 0}, {0.5f, 0.5f, 0}, {-0.5f, 0.5f, 0}};
  m.indices = {0, 1, 2, 0, 2, 3};
  return m;
}

Scene quad_scene(int instances) {
  Scene s;
  s.materials.push_back(make_material("name = \"grey\""));
  s.prototypes.push_back(Prototype{"quad", {unit_quad()}});
  for (int i = 0; i < instances; ++i) {
    Instance inst;
    inst.world_from_object = Transform::translate({1, 0, 0});
    inst.motion = {Transform(), Transform::translate({2, 0, 0})};
    if (i > 0)
      inst.world_from_object = inst.motion[0] = inst.motion[1] = Transform::translate({0, 50, 0});
    s.instances.push_back(inst);
  }
  return s;
}

Ray down(double x, double y, double time) { return Ray{{x, y, 5}, {0, 0, -1}, 0, kInf, time}; }

// The quad moves from x = 0 to x = 2 over the shutter: a ray at x = 1.2 meets it for times in
// [0.35, 0.85], at the point (1.2 - 2 time, 0.1) of the quad; once flattened (one use), once as
// an instance (two uses).
TEST(MotionBlurAccel, TranslatingQuadIsMetWhereItIsAtTheRayTime) {
  for (int uses : {1, 2}) {
    const Scene s = quad_scene(uses);
    const Accel accel(s);
    EXPECT_TRUE(accel.has_motion());
    EXPECT_EQ(accel.record(0).kind,
              uses == 1 ? Accel::Record::Kind::FlatMesh : Accel::Record::Kind::Instance);
    for (double time : {0.0, 0.3, 0.34, 0.36, 0.5, 0.84, 0.86, 1.0}) {
      Hit h;
      const bool hit = accel.intersect(down(1.2, 0.1, time), &h);
      EXPECT_EQ(hit, time > 0.35 && time < 0.85) << "uses " << uses << " time " << time;
      if (!hit) continue;
      EXPECT_NEAR(h.t, 5, 1e-6);
      EXPECT_NEAR(h.p.x, 1.2, 1e-6) << "uses " << uses << " time " << time;
      EXPECT_NEAR(h.p_object.x, uses == 1 ? 1.2 : 1.2 - 2 * time, 1e-6) << time;
      EXPECT_EQ(h.time, time);
    }
  }
}

// A quad turning 90 degrees about z over 5 steps (linear between them): at each step's time the
// hit's object-space point is the world point turned back; at every time the hit lies on the ray.
TEST(MotionBlurAccel, RotatingInstanceHitsOnTheRayAtItsPose) {
  Scene s = quad_scene(2);
  for (Instance& inst : s.instances) {
    inst.motion.clear();
    for (int k = 0; k < 5; ++k) inst.motion.push_back(Transform::rotate(22.5 * k, {0, 0, 1}));
    inst.world_from_object = inst.motion[2];
  }
  s.instances[1].motion.assign(5, Transform::translate({0, 50, 0}));
  const Accel accel(s);
  for (int k = 0; k <= 8; ++k) {
    const double time = k / 8.0;
    Hit h;
    ASSERT_TRUE(accel.intersect(down(0.3, 0.2, time), &h)) << time;
    EXPECT_NEAR(length(h.p - Vec3{0.3, 0.2, 0}), 0, 1e-6) << time;
    if (k % 2) continue;
    const Vec3 back = Transform::rotate(-22.5 * (k / 2), {0, 0, 1}).point({0.3, 0.2, 0});
    EXPECT_NEAR(length(h.p_object - back), 0, 1e-6) << "time " << time;
  }
}

// A quad whose vertices rise from z = 0 to z = 1 over the shutter (two steps): met at depth
// 5 - time, its normal up throughout.
TEST(MotionBlurAccel, DeformingMeshIsMetAtItsInterpolatedDepth) {
  for (int uses : {1, 2}) {
    Scene s = quad_scene(uses);
    TriangleMesh& m = s.prototypes[0].meshes[0];
    std::vector<Vec3f> up = m.positions;
    for (Vec3f& p : up) p.z = 1;
    m.motion_positions = {m.positions, up};
    for (Instance& inst : s.instances) inst.motion.clear();
    s.instances[0].world_from_object = Transform();
    const Accel accel(s);
    for (double time : {0.0, 0.25, 0.7, 1.0}) {
      Hit h;
      ASSERT_TRUE(accel.intersect(down(0.1, 0.1, time), &h)) << time;
      EXPECT_NEAR(h.t, 5 - time, 1e-6) << "uses " << uses << " time " << time;
      EXPECT_NEAR(h.p.z, time, 1e-6) << "uses " << uses << " time " << time;
      EXPECT_NEAR(std::abs(h.ng.z), 1, 1e-9);
    }
  }
}

}  // namespace
}  // namespace anamorph
