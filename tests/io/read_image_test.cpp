// read_image on fixtures written by tests/data/io/make_fixtures.py (not by our encoders).
#include <gtest/gtest.h>

#include <cmath>

#include "io/image_io.h"
#include "io/io_test_util.h"
#include "test_util.h"

namespace anamorph {

namespace {
std::filesystem::path fixture(const char* name) { return test::data_dir() / "io" / name; }
}  // namespace

TEST(ReadImage, GreyPngExpandsToRgbaAndLinearizes) {
  const Image img = read_image(fixture("grey.png"));
  ASSERT_EQ(img.width, 3);
  ASSERT_EQ(img.height, 1);
  ASSERT_EQ(img.channels, 4);
  ASSERT_EQ(img.pixels.size(), 12u);
  const int grey[3] = {0, 188, 255};
  for (int x = 0; x < 3; ++x) {
    for (int c = 0; c < 3; ++c)
      EXPECT_FLOAT_EQ(img.at(x, 0, c), srgb_to_linear(grey[x] / 255.0f)) << "x=" << x;
    EXPECT_EQ(img.at(x, 0, 3), 1.0f) << "x=" << x;
  }
  EXPECT_NEAR(img.at(1, 0, 0), 0.5029f, 1e-4);  // 188 is about half intensity
}

TEST(ReadImage, DataTexturesAreNotLinearized) {
  const Image img = read_image(fixture("grey.png"), /*srgb=*/false);
  ASSERT_EQ(img.width, 3);
  EXPECT_FLOAT_EQ(img.at(1, 0, 0), 188 / 255.0f);
  EXPECT_FLOAT_EQ(img.at(2, 0, 2), 1.0f);
}

TEST(ReadImage, SixteenBitPngKeepsPrecision) {
  const Image img = read_image(fixture("grey16.png"));
  ASSERT_EQ(img.width, 1);
  EXPECT_NEAR(img.at(0, 0, 1), srgb_to_linear(32768.0f / 65535.0f), 1e-6);
  EXPECT_EQ(img.at(0, 0, 3), 1.0f);
}

TEST(ReadImage, HdrIsLinearAndExact) {
  const Image img = read_image(fixture("tiny.hdr"));
  ASSERT_EQ(img.width, 2);
  ASSERT_EQ(img.height, 1);
  const float want[2][4] = {{0.5f, 1.0f, 2.0f, 1.0f}, {0.25f, 0.125f, 3.0f, 1.0f}};
  for (int x = 0; x < 2; ++x)
    for (int c = 0; c < 4; ++c) EXPECT_EQ(img.at(x, 0, c), want[x][c]) << x << "," << c;
}

TEST(ReadImage, MissingFileIsNamed) {
  const auto path = fixture("no-such-image.png");
  const std::string msg = test::error_of([&] { read_image(path); });
  EXPECT_NE(msg.find(path.string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("No such file"), std::string::npos) << msg;
}

TEST(ReadImage, CorruptFileIsNamed) {
  const auto path = fixture("corrupt.png");
  const std::string msg = test::error_of([&] { read_image(path); });
  EXPECT_NE(msg.find(path.string()), std::string::npos) << msg;
}

class ReadImageScratch : public test::ScratchDir {};

TEST_F(ReadImageScratch, UnsupportedFileIsNamed) {
  const auto path = dir() / "notes.png";
  test::write_bytes(path, "this is not an image\n");
  const std::string msg = test::error_of([&] { read_image(path); });
  EXPECT_NE(msg.find(path.string()), std::string::npos) << msg;
  const std::string meta_msg = test::error_of([&] { read_metadata(path); });
  EXPECT_NE(meta_msg.find(path.string()), std::string::npos) << meta_msg;
}

TEST(ReadImage, SharedGltfTexture) {
  ANAMORPH_REQUIRE_SHARED();
  const auto path = test::shared_scenes() / "gltf/BoxTextured-glTF/CesiumLogoFlat.png";
  const Image img = read_image(path);
  EXPECT_EQ(img.width, 211);
  EXPECT_EQ(img.height, 211);
  ASSERT_EQ(img.pixels.size(), size_t(211) * 211 * 4);
  for (float v : img.pixels) ASSERT_TRUE(v >= 0.0f && v <= 1.0f) << v;
}

}  // namespace anamorph
