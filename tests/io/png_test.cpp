#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>

#include <tbb/task_arena.h>

#include "io/image_io.h"
#include "io/io_test_util.h"
#include "render/film.h"

namespace anamorph {

namespace {

OutputImage rgba_image(int w, int h) {
  OutputImage img;
  img.width = w;
  img.height = h;
  img.layers.push_back({"", {"R", "G", "B", "A"}, std::vector<float>(size_t(w) * h * 4)});
  return img;
}

// How often a 4-byte chunk type occurs in a file (chunk types never occur in compressed data
// of these small images by accident, and the test checks exact counts).
int count_of(const std::vector<unsigned char>& bytes, const char* type) {
  int n = 0;
  for (size_t i = 0; i + 4 <= bytes.size(); ++i) n += std::memcmp(&bytes[i], type, 4) == 0;
  return n;
}

const std::map<std::string, std::string> kMetadata = {
    {"anamorph.camera",
     "[camera]\ntype = \"fisheye\"\nfov = 180.0\norigin = \"sphere(u, v)\"\n\n[camera.lens]\n"
     "shift = [0.1, -0.2]\n"},
    {"anamorph.command", "anamorph render scene.toml -o out.png --spp 64"},
    {"utf8", "Bildschärfe \xe2\x80\x94 \xcf\x80 \xe2\x89\x88 3.14159 \xf0\x9f\x8e\xa5"},
    {"latin1", "caf\xc3\xa9 cr\xc3\xa8me"},
    {"empty", ""},
};

}  // namespace

class Png : public test::ScratchDir {};

// A gradient with varying alpha, including (near-)transparent pixels whose straight colour
// must survive: PNG stores un-premultiplied colour.
TEST_F(Png, RoundTripWithinQuantization) {
  const int w = 64, h = 16;
  OutputImage img = rgba_image(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      float* p = &img.layers[0].data[(size_t(y) * w + x) * 4];
      p[0] = float(x) / (w - 1);
      p[1] = float(y) / (h - 1);
      p[2] = 0.5f * float(x + y) / (w + h - 2) + 0.001f;
      p[3] = float((x * 7 + y * 13) % 256) / 255.0f + (x % 3 - 1) * 0.0011f;
      p[3] = std::min(std::max(p[3], 0.0f), 1.0f);
    }
  const auto path = dir() / "gradient.png";
  write_png(path, img);
  const Image back = read_image(path);
  ASSERT_EQ(back.width, w);
  ASSERT_EQ(back.height, h);
  float worst_colour = 0, worst_alpha = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float* p = &img.layers[0].data[(size_t(y) * w + x) * 4];
      for (int c = 0; c < 3; ++c) {
        const float err = std::abs(linear_to_srgb(back.at(x, y, c)) - linear_to_srgb(p[c]));
        worst_colour = std::max(worst_colour, err);
        ASSERT_LE(err, 0.5f / 255 + 1e-5f) << "pixel " << x << "," << y << " c" << c << ": wrote "
                                           << p[c] << " read " << back.at(x, y, c);
      }
      const float err = std::abs(back.at(x, y, 3) - p[3]);
      worst_alpha = std::max(worst_alpha, err);
      ASSERT_LE(err, 0.5f / 255 + 1e-6f)
          << "pixel " << x << "," << y << ": alpha " << p[3] << " read " << back.at(x, y, 3);
    }
  // Quantization really happened (an 8-bit file), but no more than rounding.
  EXPECT_GT(worst_colour, 0.0f);
  EXPECT_GT(worst_alpha, 0.0f);
}

// Taller than one compression band (64 rows), odd width, noisy content (every row filter gets
// used): read back, every byte is the exact 8-bit code; the file has the same bytes whether it
// was encoded on one thread or several.
TEST_F(Png, ManyBandsRoundTripExactlyAndDoNotDependOnThreads) {
  const int w = 137, h = 200;
  OutputImage img = rgba_image(w, h);
  uint32_t state = 12345;
  for (size_t i = 0; i < img.layers[0].data.size(); ++i) {
    state = state * 1664525u + 1013904223u;
    const float noise = float(state >> 8) / float(1u << 24);
    const size_t px = i / 4;
    // Smooth areas (none/up filters) and noise (sub), alpha in (0, 1].
    img.layers[0].data[i] = (px / w) % 3 == 0 ? noise : float(px % w) / float(w);
    if (i % 4 == 3) img.layers[0].data[i] = 0.25f + 0.75f * noise;
  }
  const auto one = dir() / "one.png", many = dir() / "many.png";
  tbb::task_arena(1).execute([&] { write_png(one, img); });
  tbb::task_arena(4).execute([&] { write_png(many, img); });
  const auto bytes = [](const std::filesystem::path& p) {
    std::ifstream f(p, std::ios::binary);
    return std::vector<char>(std::istreambuf_iterator<char>(f), {});
  };
  EXPECT_EQ(bytes(one), bytes(many)) << "PNG bytes depend on the thread count";
  const Image back = read_image(one);
  ASSERT_EQ(back.width, w);
  ASSERT_EQ(back.height, h);
  int bad = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) {
        const float v = img.layers[0].data[(size_t(y) * w + x) * 4 + size_t(c)];
        // read_image decodes to linear: re-encode to compare codes.
        const int code = int(std::lround(linear_to_srgb(back.at(x, y, c)) * 255.0f));
        if (code != int(linear_to_srgb8(v)) && ++bad <= 5)
          ADD_FAILURE() << "pixel " << x << "," << y << " c" << c << ": wrote " << v << " (code "
                        << int(linear_to_srgb8(v)) << "), read code " << code;
      }
  EXPECT_EQ(bad, 0);
}

TEST_F(Png, OutOfRangeValuesAreClampedAndRgbIsOpaque) {
  OutputImage img;
  img.width = 4;
  img.height = 1;
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  img.layers.push_back(
      {"", {"R", "G", "B"}, {-0.5f, 1.5f, nan, inf, -inf, 0.25f, 0, 0, 1, 1, 1, 0}});
  const auto path = dir() / "clamp.png";
  write_png(path, img);
  const Image back = read_image(path);
  ASSERT_EQ(back.width, 4);
  const float want[4][3] = {{0, 1, 0},
                            {1, 0, srgb_to_linear(std::round(linear_to_srgb(0.25f) * 255) / 255)},
                            {0, 0, 1},
                            {1, 1, 0}};
  for (int x = 0; x < 4; ++x) {
    for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(back.at(x, 0, c), want[x][c]) << x << "," << c;
    EXPECT_EQ(back.at(x, 0, 3), 1.0f) << x;
  }
}

// read_metadata checks the CRC of every chunk, including those stb wrote, so a wrong CRC
// in our own chunks could not pass unnoticed alongside correct ones.
TEST_F(Png, MetadataRoundTrip) {
  OutputImage img = rgba_image(3, 2);
  img.metadata = kMetadata;
  const auto path = dir() / "meta.png";
  write_png(path, img);
  const auto back = read_metadata(path);
  EXPECT_EQ(back, kMetadata);
  for (const auto& [k, v] : kMetadata) {
    ASSERT_TRUE(back.count(k)) << "missing key " << k;
    EXPECT_EQ(back.at(k), v) << "key " << k;
  }
  // Latin-1 values in tEXt, the one beyond Latin-1 in iTXt.
  const auto bytes = test::file_bytes(path);
  EXPECT_EQ(count_of(bytes, "tEXt"), 4);
  EXPECT_EQ(count_of(bytes, "iTXt"), 1);
  // The pixels are still a valid image after the chunk splice.
  const Image pixels = read_image(path);
  EXPECT_EQ(pixels.width, 3);
  EXPECT_EQ(pixels.height, 2);
}

TEST_F(Png, BadMetadataKeyIsRefusedAndNothingWritten) {
  for (const std::string& key : {std::string(80, 'k'), std::string(), std::string("tab\tkey"),
                                 std::string("\xcf\x80 key")}) {
    OutputImage img = rgba_image(1, 1);
    img.metadata[key] = "value";
    const std::string msg = test::error_of([&] { write_png(dir() / "bad.png", img); });
    EXPECT_NE(msg.find("metadata key '" + key + "'"), std::string::npos) << msg;
    EXPECT_TRUE(test::dir_entries(dir()).empty());
  }
}

TEST_F(Png, WrongLayerSizeIsRefused) {
  OutputImage img = rgba_image(2, 2);
  img.layers[0].data.pop_back();
  const std::string msg = test::error_of([&] { write_png(dir() / "short.png", img); });
  EXPECT_NE(msg.find("short.png"), std::string::npos) << msg;
  EXPECT_NE(msg.find("expected 2x2x4 = 16"), std::string::npos) << msg;
  EXPECT_TRUE(test::dir_entries(dir()).empty());
}

TEST_F(Png, WriteImageDispatchesByExtensionIgnoringCase) {
  const OutputImage img = rgba_image(2, 2);
  write_image(dir() / "a.PNG", img);
  write_image(dir() / "b.Exr", img);
  const auto png = test::file_bytes(dir() / "a.PNG");
  const auto exr = test::file_bytes(dir() / "b.Exr");
  ASSERT_GE(png.size(), 8u);
  ASSERT_GE(exr.size(), 4u);
  EXPECT_EQ(std::memcmp(png.data(), "\x89PNG\r\n\x1a\n", 8), 0);
  EXPECT_EQ(std::memcmp(exr.data(), "\x76\x2f\x31\x01", 4), 0);
}

TEST_F(Png, UnsupportedExtensionListsSupportedOnes) {
  const std::string msg = test::error_of([&] { write_image(dir() / "a.tif", rgba_image(1, 1)); });
  EXPECT_NE(msg.find("a.tif"), std::string::npos) << msg;
  EXPECT_NE(msg.find(".png"), std::string::npos) << msg;
  EXPECT_NE(msg.find(".exr"), std::string::npos) << msg;
  EXPECT_TRUE(test::dir_entries(dir()).empty());
}

// A render's beauty written from 8-bit pixels (Film::output_rgba8, what `anamorph render` does for
// a PNG without AOV layers) is the same file, byte for byte, as through the float output layer:
// several samples per pixel, values above 1, partial coverage and pixels without a ray.
TEST_F(Png, FilmStraightTo8BitsEqualsTheFloatLayerPath) {
  Film film(37, 23, {});
  for (int y = 0; y < 23; ++y)
    for (int x = 0; x < 37; ++x)
      for (int s = 0; s < 1 + (x + y) % 3; ++s) {
        const bool ray = (x * 7 + y * 3 + s) % 5 != 0;
        const Color L{0.03 * x, 0.05 * y, 1.7 * std::sin(0.3 * (x + s))};
        film.add(x, y, ray ? L : Color{}, ray ? 1.0 : 0.0, AovSample{});
      }
  OutputImage img = film.output();
  img.metadata = kMetadata;
  write_png(dir() / "float.png", img);
  write_png(dir() / "bytes.png", Rgba8Image{37, 23, film.output_rgba8(), kMetadata});
  const auto a = test::file_bytes(dir() / "float.png"), b = test::file_bytes(dir() / "bytes.png");
  ASSERT_EQ(a.size(), b.size());
  EXPECT_TRUE(a == b) << "the two PNG files differ";
  // Partial coverage made it into the file (the test covers what it claims).
  const Image back = read_image(dir() / "bytes.png", /*srgb=*/false);
  int partial = 0;
  for (int i = 0; i < back.width * back.height; ++i) {
    const float alpha = back.pixels[size_t(i) * size_t(back.channels) + 3];
    partial += alpha > 0.01f && alpha < 0.99f;
  }
  EXPECT_GT(partial, 0) << "no pixel with partial coverage";
}

}  // namespace anamorph
