// Ray packets as the renderer traces primary rays: the structure-of-arrays entry point gives the
// same hits, bit for bit, as the Ray-array one, and without surface data it still gives t, the
// ids and the material.
#include <gtest/gtest.h>

#include <cstring>

#include "accel/accel.h"
#include "scene/scene_loader.h"
#include "test_util.h"

namespace anamorph {

namespace {

// Every kind of top-level geometry: an analytic shape, a mesh moved to world space, and an
// instanced mesh (a glTF mesh used by several nodes).
Scene mixed_scene() {
  const std::string gltf = (test::data_dir() / "models" / "shared_mesh.gltf").string();
  const std::string obj = (test::data_dir() / "models" / "textured_quad.obj").string();
  return load_scene_from_string(
      "[[material]]\nname = \"red\"\ncolor = [0.8, 0.1, 0.1]\n"
      "[[object]]\ntype = \"sphere\"\ncenter = [0, -1.2, -6]\nradius = 0.8\nmaterial = \"red\"\n"
      "[[object]]\ntype = \"mesh\"\nfile = \"" +
          obj +
          "\"\ntransform = { translate = [1.5, 0, -4] }\n"
          "[[object]]\ntype = \"mesh\"\nfile = \"" +
          gltf + "\"\ntransform = { translate = [-3.5, 0.2, -5] }\n",
      "t.toml");
}

bool same_bits(const Vec3& a, const Vec3& b) { return std::memcmp(&a, &b, sizeof(Vec3)) == 0; }

}  // namespace

TEST(Packets, ArraysOfComponentsTraceLikeRays) {
  const Scene scene = mixed_scene();
  const Accel accel(scene);
  int hit_kinds[3] = {0, 0, 0};  // shape, flat mesh, instance
  for (int packet = 0; packet < 64; ++packet) {
    Ray rays[16];
    double org[3][16], dir[3][16];
    bool valid[16];
    for (int i = 0; i < 16; ++i) {
      // A fan of directions from the origin across all three objects.
      const double x = -0.9 + 1.8 * ((packet % 8) * 4 + (i & 3)) / 31.0;
      const double y = -0.5 + 1.0 * ((packet / 8) * 4 + (i >> 2)) / 31.0;
      rays[i] = Ray{{0.01 * i, 0.02, 0}, normalize(Vec3{x, y, -1}), 0, kInf};
      for (int c = 0; c < 3; ++c) org[c][i] = rays[i].o[c], dir[c][i] = rays[i].d[c];
      valid[i] = (i + packet) % 7 != 0;  // some lanes masked off
    }
    Hit a[16], b[16], c[16];
    bool fa[16], fb[16], fc[16];
    accel.intersect16(rays, valid, a, fa);
    accel.intersect16(org, dir, valid, b, fb);
    accel.intersect16(org, dir, valid, c, fc, /*surface=*/false);
    for (int i = 0; i < 16; ++i) {
      SCOPED_TRACE(testing::Message() << "packet " << packet << " lane " << i);
      ASSERT_EQ(fa[i], fb[i]);
      ASSERT_EQ(fa[i], fc[i]);
      if (!valid[i]) {
        EXPECT_FALSE(fa[i]) << "a masked lane reported a hit";
      }
      if (!fa[i]) continue;
      EXPECT_EQ(a[i].t, b[i].t);
      EXPECT_TRUE(same_bits(a[i].p, b[i].p));
      EXPECT_TRUE(same_bits(a[i].ng, b[i].ng));
      EXPECT_TRUE(same_bits(a[i].ns, b[i].ns));
      EXPECT_TRUE(same_bits(a[i].dpdu, b[i].dpdu));
      EXPECT_EQ(a[i].uv.x, b[i].uv.x);
      EXPECT_EQ(a[i].uv.y, b[i].uv.y);
      EXPECT_EQ(a[i].material, b[i].material);
      EXPECT_EQ(a[i].object_id, b[i].object_id);
      // Without surface data: the same t, ids and material.
      EXPECT_EQ(a[i].t, c[i].t);
      EXPECT_EQ(a[i].object_id, c[i].object_id);
      EXPECT_EQ(a[i].mesh, c[i].mesh);
      EXPECT_EQ(a[i].prim, c[i].prim);
      EXPECT_EQ(a[i].material, c[i].material)
          << "object " << a[i].object_id << " kind " << int(accel.record(a[i].object_id).kind);
      hit_kinds[int(accel.record(a[i].object_id).kind) == 2   ? 0
                : int(accel.record(a[i].object_id).kind) == 0 ? 1
                                                              : 2]++;
    }
  }
  // The fan must reach every kind of geometry, or the test proves less than it says.
  EXPECT_GT(hit_kinds[0], 0) << "no lane hit the sphere";
  EXPECT_GT(hit_kinds[1], 0) << "no lane hit the flat mesh";
  EXPECT_GT(hit_kinds[2], 0) << "no lane hit the instanced mesh";
}

}  // namespace anamorph
