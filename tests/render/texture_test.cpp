// Procedural and image textures: exact values, footprint filtering, wrap modes.
#include <gtest/gtest.h>

#include "material/texture.h"

namespace anamorph {

TEST(Texture, CheckerAlternatesAndIgnoresTheNormalAxis) {
  Texture t;
  t.kind = Texture::Kind::Checker;
  t.space = Texture::Space::World;
  t.color_a = Color(1);
  t.color_b = Color(0);
  TexCoord tc;
  tc.n_world = {0, 1, 0};
  tc.p_world = {0.5, 0.0, 0.5};
  EXPECT_EQ(t.eval(tc).x, 1.0);
  tc.p_world = {1.5, 0.0, 0.5};
  EXPECT_EQ(t.eval(tc).x, 0.0);
  // On the floor y = 0 the value must not flicker with y's rounding.
  tc.p_world = {1.5, -1e-12, 0.5};
  EXPECT_EQ(t.eval(tc).x, 0.0);
}

TEST(Texture, CheckerFilteredOverManyCellsIsGrey) {
  Texture t;
  t.kind = Texture::Kind::Checker;
  t.space = Texture::Space::Uv;
  t.color_a = Color(1);
  t.color_b = Color(0);
  TexCoord tc;
  tc.uv = {0.3, 0.7};
  tc.duvdx = {50, 0};
  tc.duvdy = {0, 50};
  EXPECT_NEAR(t.eval(tc).x, 0.5, 0.02);
}

TEST(Texture, GridLinesCoverTheirWidth) {
  Texture t;
  t.kind = Texture::Kind::Grid;
  t.space = Texture::Space::Uv;
  t.line_width = 0.1;
  t.color_a = Color(0);
  t.color_b = Color(1);
  TexCoord tc;
  tc.uv = {0.02, 0.5};  // within 0.05 of the u = 0 line
  EXPECT_EQ(t.eval(tc).x, 1.0);
  tc.uv = {0.5, 0.5};
  EXPECT_EQ(t.eval(tc).x, 0.0);
  // Heavily filtered: the covered fraction is 1 - (1 - 0.1)^2 = 0.19.
  tc.duvdx = {40, 0};
  tc.duvdy = {0, 40};
  EXPECT_NEAR(t.eval(tc).x, 0.19, 0.01);
}

TEST(Texture, MipMapAveragesAndWraps) {
  Image im;
  im.width = 4;
  im.height = 4;
  im.pixels.resize(64);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x)
      for (int c = 0; c < 4; ++c) im.at(x, y, c) = float((x + y) % 2);
  const MipMap mip(im);
  EXPECT_EQ(mip.levels(), 3);
  float out[4];
  mip.lookup({0.5, 0.5}, 1.0, Wrap::Repeat, Wrap::Repeat, false, out);  // whole-image footprint
  EXPECT_NEAR(out[0], 0.5, 1e-6);
  mip.lookup({0.125 + 1, 0.125}, 0, Wrap::Repeat, Wrap::Repeat, true, out);  // repeat wraps u
  EXPECT_EQ(out[0], 0.0f);
  mip.lookup({0.125 + 0.25, 0.125}, 0, Wrap::Repeat, Wrap::Repeat, true, out);
  EXPECT_EQ(out[0], 1.0f);
}

TEST(Texture, KhrTextureTransformRotation) {
  // KHR_texture_transform: rotation by +90 degrees maps (1, 0) to (0, -1).
  const UvTransform t = UvTransform::from_offset_rotation_scale({0, 0}, kPi / 2, {1, 1});
  const Vec2 p = t.apply({1, 0});
  EXPECT_NEAR(p.x, 0, 1e-12);
  EXPECT_NEAR(p.y, -1, 1e-12);
}

}  // namespace anamorph
