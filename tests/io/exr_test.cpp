#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>

#include <tinyexr.h>

#include "io/image_io.h"
#include "io/io_test_util.h"

namespace anamorph {

namespace {

// Deterministic values that stress a float codec: signs, zero, -0, denormals, huge, inf, NaN.
float test_value(uint32_t i) {
  switch (i % 11) {
    case 0:
      return -0.0f;
    case 1:
      return std::numeric_limits<float>::denorm_min() * float(i);
    case 2:
      return 3.0e38f;
    case 3:
      return std::numeric_limits<float>::infinity();
    case 4:
      return std::numeric_limits<float>::quiet_NaN();
    default: {
      uint32_t h = i * 2654435761u;
      h ^= h >> 15;
      return (float(h % 200001u) - 100000.0f) * 1e-3f;
    }
  }
}

// Beauty RGBA, "albedo" RGB, "depth" Z; layers deliberately not in sorted order.
OutputImage layered(int w, int h) {
  OutputImage img;
  img.width = w;
  img.height = h;
  const size_t n = size_t(w) * h;
  img.layers = {{"", {"R", "G", "B", "A"}, std::vector<float>(n * 4)},
                {"depth", {"Z"}, std::vector<float>(n)},
                {"albedo", {"R", "G", "B"}, std::vector<float>(n * 3)}};
  uint32_t k = 1;
  for (ImageLayer& l : img.layers)
    for (float& v : l.data) v = test_value(k++);
  return img;
}

}  // namespace

class Exr : public test::ScratchDir {};

TEST_F(Exr, MultiLayerRoundTripIsBitExact) {
  const int w = 7, h = 5;
  const OutputImage img = layered(w, h);
  const auto path = dir() / "layers.exr";
  write_exr(path, img);

  int rw = 0, rh = 0;
  const auto channels = read_exr_channels(path, &rw, &rh);
  ASSERT_EQ(rw, w);
  ASSERT_EQ(rh, h);
  std::vector<std::string> names;
  for (const auto& [name, plane] : channels) names.push_back(name);
  EXPECT_EQ(names, (std::vector<std::string>{"A", "B", "G", "R", "albedo.B", "albedo.G", "albedo.R",
                                             "depth.Z"}));
  for (const ImageLayer& l : img.layers)
    for (size_t c = 0; c < l.channels.size(); ++c) {
      const std::string name = l.name.empty() ? l.channels[c] : l.name + "." + l.channels[c];
      ASSERT_TRUE(channels.count(name)) << "missing channel " << name;
      const std::vector<float>& plane = channels.at(name);
      ASSERT_EQ(plane.size(), size_t(w) * h) << name;
      for (size_t i = 0; i < plane.size(); ++i) {
        const float want = l.data[i * l.channels.size() + c];
        ASSERT_EQ(std::bit_cast<uint32_t>(plane[i]), std::bit_cast<uint32_t>(want))
            << name << " pixel " << i << ": wrote " << want << " read " << plane[i];
      }
    }

  // The beauty layer is what read_image shows, unchanged (EXR is linear).
  const Image beauty = read_image(path);
  ASSERT_EQ(beauty.pixels.size(), img.layers[0].data.size());
  EXPECT_EQ(std::memcmp(beauty.pixels.data(), img.layers[0].data.data(),
                        beauty.pixels.size() * sizeof(float)),
            0);
}

// OpenEXR lays pixel data out in sorted channel order, so the file's list must be sorted.
TEST_F(Exr, ChannelListIsSortedInTheFile) {
  const auto path = dir() / "sorted.exr";
  write_exr(path, layered(3, 2));
  EXRVersion version;
  ASSERT_EQ(ParseEXRVersionFromFile(&version, path.c_str()), TINYEXR_SUCCESS);
  EXRHeader header;
  InitEXRHeader(&header);
  const char* err = nullptr;
  ASSERT_EQ(ParseEXRHeaderFromFile(&header, &version, path.c_str(), &err), TINYEXR_SUCCESS);
  std::vector<std::string> names;
  for (int i = 0; i < header.num_channels; ++i) {
    names.push_back(header.channels[i].name);
    EXPECT_EQ(header.pixel_types[i], TINYEXR_PIXELTYPE_FLOAT) << names.back();
  }
  FreeEXRHeader(&header);
  EXPECT_EQ(names, (std::vector<std::string>{"A", "B", "G", "R", "albedo.B", "albedo.G", "albedo.R",
                                             "depth.Z"}));
}

TEST_F(Exr, MetadataRoundTrip) {
  OutputImage img = layered(2, 2);
  img.metadata = {
      {"anamorph.camera", "[camera]\ntype = \"fisheye\"\nfov = 180.0\n\n[camera.lens]\nk = 1\n"},
      {"anamorph.command", "anamorph render scene.toml -o out.exr"},
      {"utf8", "Bildschärfe \xe2\x80\x94 \xcf\x80 \xe2\x89\x88 3.14159 \xf0\x9f\x8e\xa5"},
      {"empty", ""},
  };
  const auto path = dir() / "meta.exr";
  write_exr(path, img);
  const auto back = read_metadata(path);
  EXPECT_EQ(back, img.metadata);
  for (const auto& [k, v] : img.metadata) {
    ASSERT_TRUE(back.count(k)) << "missing key " << k;
    EXPECT_EQ(back.at(k), v) << "key " << k;
  }
}

TEST_F(Exr, InvalidInputsAreRefusedAndNothingWritten) {
  OutputImage reserved = layered(1, 1);
  reserved.metadata["channels"] = "x";
  EXPECT_NE(test::error_of([&] { write_exr(dir() / "a.exr", reserved); }).find("'channels'"),
            std::string::npos);

  OutputImage duplicate = layered(1, 1);
  duplicate.layers.push_back(duplicate.layers[2]);  // a second "albedo"
  EXPECT_NE(test::error_of([&] {
              write_exr(dir() / "a.exr", duplicate);
            }).find("duplicate channel 'albedo.B'"),
            std::string::npos);

  OutputImage short_layer = layered(2, 2);
  short_layer.layers[1].data.resize(3);
  const std::string msg = test::error_of([&] { write_exr(dir() / "a.exr", short_layer); });
  EXPECT_NE(msg.find("layer 'depth' holds 3 values"), std::string::npos) << msg;
  EXPECT_NE(msg.find("a.exr"), std::string::npos) << msg;

  EXPECT_TRUE(test::dir_entries(dir()).empty());
}

TEST_F(Exr, CorruptFileIsNamed) {
  const auto good = dir() / "good.exr";
  write_exr(good, layered(4, 4));
  auto bytes = test::file_bytes(good);
  const auto bad = dir() / "truncated.exr";
  test::write_bytes(bad, std::string(bytes.begin(), bytes.begin() + long(bytes.size() / 2)));
  for (auto f : {+[](const std::filesystem::path& p) { read_image(p); },
                 +[](const std::filesystem::path& p) { read_exr_channels(p, nullptr, nullptr); }}) {
    const std::string msg = test::error_of([&] { f(bad); });
    EXPECT_NE(msg.find(bad.string()), std::string::npos) << msg;
  }
}

}  // namespace anamorph
