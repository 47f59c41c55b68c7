// read_image on fixtures written by tests/data/io/make_fixtures.py (not by our encoders).
#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>

#include <filesystem>
#include <fstream>

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

namespace anamorph {

namespace {

// A W x H Radiance file, every scanline new-style RLE (one run per channel) or flat RGBE.
std::string hdr_file(int w, int h, bool rle) {
  std::string s = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y " + std::to_string(h) + " +X " +
                  std::to_string(w) + "\n";
  const unsigned char rgbe[4] = {128, 64, 32, 129};  // (1, 0.5, 0.25)
  for (int y = 0; y < h; ++y) {
    if (rle) {
      s += {char(2), char(2), char(w >> 8), char(w & 255)};
      for (const unsigned char c : rgbe) s += {char(128 + w), char(c)};  // w <= 127
    } else {
      for (int x = 0; x < w; ++x) s.append(reinterpret_cast<const char*>(rgbe), 4);
    }
  }
  return s;
}

}  // namespace

// stb_image reads past the end of a cut HDR file as zeros (a partly black sky); the scanlines
// present are counted first.
TEST_F(ReadImageScratch, TruncatedHdrIsAnError) {
  for (const bool rle : {true, false}) {
    const std::string full = hdr_file(16, 12, rle);
    const auto whole = dir() / "whole.hdr", cut = dir() / "cut.hdr";
    std::ofstream(whole, std::ios::binary) << full;
    const Image img = read_image(whole);
    ASSERT_EQ(img.width, 16);
    EXPECT_FLOAT_EQ(img.at(15, 11, 0), 1.0f) << "rle " << rle;
    EXPECT_FLOAT_EQ(img.at(15, 11, 2), 0.25f) << "rle " << rle;
    const size_t line = rle ? 4 + 4 * 2 : 16 * 4, header = full.size() - 12 * line;
    const size_t keep = full.size() * 2 / 3, present = (keep - header) / line;
    std::ofstream(cut, std::ios::binary) << full.substr(0, keep);
    const std::string msg = test::error_of([&] { read_image(cut); });
    EXPECT_NE(msg.find("the HDR file is cut short: " + std::to_string(present) +
                       " of its 12 scanlines are present"),
              std::string::npos)
        << "rle " << rle << ": " << msg;
  }
}

}  // namespace anamorph

namespace anamorph {

// An image must fit its file: 86 bytes found by fuzz_image decoded (as a TGA) to 1.6 GB of
// pixels in 4 s; now refused from the header. A legitimately well compressed image (a flat
// 3000 x 3000 PNG, 1/1000 of its pixel bytes) still reads.
TEST_F(ReadImageScratch, ImagesMustFitTheirFiles) {
  const auto bomb = test::data_dir() / "fuzz" / "image" / "86_bytes_decoding_to_1.6_GB.tga";
  const std::string msg = test::error_of([&] { read_image(bomb); });
  EXPECT_NE(msg.find("the 86-byte file declares"), std::string::npos) << msg;
  EXPECT_NE(msg.find("a damaged file or a decompression bomb"), std::string::npos) << msg;

  OutputImage flat;
  flat.width = flat.height = 3000;
  flat.layers.push_back({"", {"R", "G", "B", "A"}, std::vector<float>(size_t(3000) * 3000 * 4)});
  const auto png = dir() / "flat.png";
  write_png(png, flat);
  const auto bytes = std::filesystem::file_size(png);
  EXPECT_LT(bytes * 100, uint64_t(3000) * 3000 * 4) << "not well compressed: " << bytes;
  const Image img = read_image(png);
  EXPECT_EQ(img.width, 3000);
  EXPECT_EQ(img.at(2999, 2999, 3), 0.0f);
}

}  // namespace anamorph

namespace anamorph {

// stb_image's HDR decoder loops forever on a run of length zero (178 bytes from fuzz_image).
TEST(ReadImage, HdrWithAZeroLengthRunIsAnErrorNotAHang) {
  const auto f = test::data_dir() / "fuzz" / "image" / "hdr_zero_length_run_hung_stb.hdr";
  const std::string msg = test::error_of([&] { read_image(f); });
  EXPECT_NE(msg.find("run-length data is corrupt"), std::string::npos) << msg;
}

}  // namespace anamorph

namespace anamorph {

// tinyexr 1.0 checks an EXR's `type` and `tiles` attributes with assert(): a bad one aborted the
// process (1548 bytes from fuzz_image). Each case is an EXR we wrote with one attribute added
// right after the version field.
std::filesystem::path exr_with_attribute(const std::string& name, const std::string& type,
                                         const std::string& value, bool tiled_flag) {
  OutputImage img;
  img.width = img.height = 2;
  img.layers = {{"", {"R", "G", "B", "A"}, std::vector<float>(16, 0.5f)}};
  const auto path = std::filesystem::temp_directory_path() /
                    ("anamorph_exr_attr_" + std::to_string(::getpid()) + ".exr");
  write_exr(path, img);
  std::string bytes = test::read_text(path);
  const uint32_t size = uint32_t(value.size());
  const std::string attr =
      name + '\0' + type + '\0' + std::string(reinterpret_cast<const char*>(&size), 4) + value;
  bytes.insert(8, attr);
  if (tiled_flag) bytes[5] = char(bytes[5] | 0x02);
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

std::string exr_error(const std::string& name, const std::string& type, const std::string& value,
                      bool tiled_flag) {
  const auto path = exr_with_attribute(name, type, value, tiled_flag);
  const std::string msg = test::error_of([&] { read_image(path); });
  std::filesystem::remove(path);
  return msg;
}

TEST(ReadImage, ExrAttributesTinyexrAssertsOnAreErrors) {
  const auto fuzz = test::data_dir() / "fuzz" / "image";
  const std::string fuzzed =
      test::error_of([&] { read_image(fuzz / "exr_type_attribute_aborted_tinyexr.exr"); });
  EXPECT_NE(fuzzed.find("its type attribute is neither scanlineimage nor tiledimage"),
            std::string::npos)
      << fuzzed;
  // A `tiledimage` type in a header that is cut short, or that a later empty type attribute
  // seemed to cancel: tinyexr asserted on both. The type is now renamed before tinyexr reads the
  // header, so each is just a damaged file.
  for (const char* f : {"exr_type_in_a_truncated_header_aborted_tinyexr.exr",
                        "exr_second_type_attribute_aborted_tinyexr.exr"}) {
    const std::string msg = test::error_of([&] { read_image(fuzz / f); });
    EXPECT_NE(msg.find("cannot read EXR"), std::string::npos) << f << ": " << msg;
  }
  EXPECT_NE(exr_error("type", "string", "deepscanline", false)
                .find("neither scanlineimage nor tiledimage"),
            std::string::npos);
  // tiledimage over scanlines (tinyexr asserted): read as the scanlines it is; it fails here only
  // because the inserted bytes moved the pixel data away from its offset table.
  const std::string tiled = exr_error("type", "string", "tiledimage", false);
  EXPECT_NE(tiled.find("decoding pixels"), std::string::npos) << tiled;
  EXPECT_NE(exr_error("tiles", "tiledesc", std::string(8, '\1'), true)
                .find("its tiles attribute has 8 bytes, not 9"),
            std::string::npos);
  // A channel list with an unknown pixel type (tinyexr asserts) or none at all (a zero-sized
  // buffer, asserted too). The inserted `channels` attribute comes first, so it is the one read.
  std::string chlist = std::string("R") + '\0';
  const int32_t bad_type = 7, one = 1;
  chlist += std::string(reinterpret_cast<const char*>(&bad_type), 4) + std::string(4, '\0') +
            std::string(reinterpret_cast<const char*>(&one), 4) +
            std::string(reinterpret_cast<const char*>(&one), 4) + '\0';
  EXPECT_NE(exr_error("channels", "chlist", chlist, false).find("channel 0 has pixel type 7"),
            std::string::npos);
  EXPECT_NE(exr_error("channels", "chlist", std::string(1, '\0'), false)
                .find("its header lists no channels"),
            std::string::npos);
  // A type attribute does not reach tinyexr, and is not reported as metadata either.
  const auto ok = exr_with_attribute("type", "string", "scanlineimage", false);
  EXPECT_EQ(read_metadata(ok).count("tyqe"), 0u);
  std::filesystem::remove(ok);
}

}  // namespace anamorph
