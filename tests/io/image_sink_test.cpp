// The output sinks' registry (io/image_sink.h): one place maps a file name to a sink kind and
// gives the one error for an unknown extension; a kind registered beside the built-in ones is
// chosen by its extension and written to through the same path.
#include <gtest/gtest.h>

#include <cstring>

#include "io/image_io.h"
#include "io/image_sink.h"
#include "io/io_test_util.h"

namespace anamorph {

namespace {

namespace fs = std::filesystem;

// `h` rows of a gradient with varying alpha, and an "albedo" layer, with metadata.
OutputImage layered(int w, int h) {
  OutputImage img;
  img.width = w;
  img.height = h;
  img.metadata = {{"anamorph.command", "anamorph render s.toml"}};
  ImageLayer beauty{"", {"R", "G", "B", "A"}, std::vector<float>(size_t(w) * size_t(h) * 4)};
  ImageLayer albedo{"albedo", {"R", "G", "B"}, std::vector<float>(size_t(w) * size_t(h) * 3)};
  for (size_t i = 0; i < size_t(w) * size_t(h); ++i) {
    for (size_t c = 0; c < 4; ++c) beauty.data[i * 4 + c] = float((i * 7 + c * 31) % 257) / 256.0f;
    for (size_t c = 0; c < 3; ++c) albedo.data[i * 3 + c] = float(i) + 0.25f * float(c);
  }
  img.layers = {beauty, albedo};
  return img;
}

std::vector<LayerSpec> specs(const OutputImage& img) {
  std::vector<LayerSpec> layers;
  for (const ImageLayer& l : img.layers) layers.push_back({l.name, l.channels});
  return layers;
}

// A kind for the test's ".rows" files: takes the albedo as floats and records every strip.
struct Recorded {
  std::vector<float> albedo;
  std::vector<int> strip_rows;
  bool committed = false;
};
Recorded* recorded = nullptr;

class RecordingSink final : public ImageSink {
 public:
  const std::vector<LayerRequest>& requests() const override {
    static const std::vector<LayerRequest> r{{"albedo", Encoding::Float32}};
    return r;
  }
  void prepare(Strip&) const override {}
  void append(const Strip& s) override {
    recorded->albedo.insert(recorded->albedo.end(), s.planes[0].f32.begin(), s.planes[0].f32.end());
    recorded->strip_rows.push_back(s.rows);
  }
  void commit() override { recorded->committed = true; }
  void commit_as(const fs::path&) override { commit(); }
};

const SinkKind kRecordingKind{
    "rows",
    {".rows"},
    [](const std::vector<LayerSpec>&) {
      return std::vector<LayerRequest>{{"albedo", Encoding::Float32}};
    },
    [](const SinkSpec&) -> std::unique_ptr<ImageSink> { return std::make_unique<RecordingSink>(); },
    1};

}  // namespace

class Sinks : public test::ScratchDir {};

TEST(SinkRegistry, TheExtensionChoosesTheKindInAnyCase) {
  ASSERT_NE(find_sink_kind("a/out.PNG"), nullptr);
  EXPECT_EQ(find_sink_kind("a/out.PNG")->name, "png");
  ASSERT_NE(find_sink_kind("out.Exr"), nullptr);
  EXPECT_EQ(find_sink_kind("out.Exr")->name, "exr");
  EXPECT_EQ(find_sink_kind("out.tif"), nullptr);
  EXPECT_EQ(find_sink_kind("no-extension-and-no-such-file"), nullptr);
}

TEST(SinkRegistry, AnUnknownExtensionNamesItAndEveryKindsExtension) {
  const std::string msg = unsupported_extension("render.tif");
  EXPECT_NE(msg.find("'.tif'"), std::string::npos) << msg;
  for (const SinkKind* k : sink_kinds())
    for (const std::string& e : k->extensions) EXPECT_NE(msg.find(e), std::string::npos) << msg;
  const std::string thrown = test::error_of([] { sink_kind("dir/render.tif"); });
  EXPECT_NE(thrown.find("dir/render.tif"), std::string::npos) << thrown;
  EXPECT_NE(thrown.find(msg), std::string::npos) << thrown;
}

// A PNG holds the beauty only: with more layers, an EXR of the same name is written beside it.
TEST(SinkRegistry, LayersAPngCannotHoldGoBesideIt) {
  const std::vector<LayerSpec> beauty{{"", {"R", "G", "B", "A"}}};
  std::vector<LayerSpec> aovs = beauty;
  aovs.push_back({"albedo", {"R", "G", "B"}});
  EXPECT_EQ(output_files("d/o.png", beauty), std::vector<fs::path>{"d/o.png"});
  EXPECT_EQ(output_files("d/o.png", aovs), (std::vector<fs::path>{"d/o.png", "d/o.exr"}));
  EXPECT_EQ(output_files("d/o.exr", aovs), std::vector<fs::path>{"d/o.exr"});
  // A strip costs a PNG 8 bytes a pixel (8-bit RGBA and its deflated band), an EXR 4 a channel.
  EXPECT_EQ(strip_bytes_per_pixel({"o.png"}, aovs), 8u);
  EXPECT_EQ(strip_bytes_per_pixel({"o.exr"}, aovs), (4u + 3u) * 4u);
  EXPECT_EQ(strip_bytes_per_pixel({"o.png", "o.exr"}, aovs), 8u + (4u + 3u) * 4u);
}

// 150 rows: two whole strips and a short one.
TEST_F(Sinks, ThePngSinkWritesTheBytesWritePngWrites) {
  const OutputImage img = layered(70, 150);
  write_image(dir() / "sink.png", img);
  write_png(dir() / "direct.png", img);
  const std::vector<unsigned char> a = test::file_bytes(dir() / "sink.png"),
                                   b = test::file_bytes(dir() / "direct.png");
  ASSERT_FALSE(a.empty());
  EXPECT_TRUE(a == b) << a.size() << " bytes through the sink, " << b.size() << " by write_png";
}

TEST_F(Sinks, TheExrSinkKeepsEveryLayerBitForBit) {
  const OutputImage img = layered(33, 130);
  write_image(dir() / "out.exr", img);
  int w = 0, h = 0;
  const auto channels = read_exr_channels(dir() / "out.exr", &w, &h);
  ASSERT_EQ(w, 33);
  ASSERT_EQ(h, 130);
  for (const ImageLayer& l : img.layers)
    for (size_t c = 0; c < l.channels.size(); ++c) {
      const std::string name = l.name.empty() ? l.channels[c] : l.name + "." + l.channels[c];
      ASSERT_TRUE(channels.count(name)) << "missing channel " << name;
      const std::vector<float>& got = channels.at(name);
      for (size_t i = 0; i < size_t(w) * size_t(h); ++i)
        ASSERT_EQ(std::memcmp(&got[i], &l.data[i * l.channels.size() + c], 4), 0)
            << name << " at pixel " << i << ": " << got[i] << " vs "
            << l.data[i * l.channels.size() + c];
    }
}

// A new output is its kind: registered, its extension chooses it, it gets the layer it asks for
// in strips from the top, and the error for an unknown extension lists it.
TEST_F(Sinks, ARegisteredKindIsChosenByItsExtensionAndGetsItsLayer) {
  Recorded rec;
  recorded = &rec;
  if (!find_sink_kind("x.rows")) register_sink_kind(kRecordingKind);
  EXPECT_THROW(register_sink_kind(kRecordingKind), std::logic_error);
  EXPECT_NE(unsupported_extension("x.tif").find(".rows"), std::string::npos);
  const OutputImage img = layered(9, 140);
  write_image(dir() / "x.ROWS", img);
  recorded = nullptr;
  EXPECT_TRUE(rec.committed);
  EXPECT_EQ(rec.strip_rows, (std::vector<int>{64, 64, 12}));
  EXPECT_TRUE(rec.albedo == img.layers[1].data)
      << rec.albedo.size() << " values recorded of " << img.layers[1].data.size();
  EXPECT_EQ(test::dir_entries(dir()), std::vector<std::string>{});  // (it writes no file)
  // A PNG with the albedo puts it in the first kind that takes every layer: the EXR, not ".rows".
  EXPECT_EQ(output_files("o.png", specs(img)), (std::vector<fs::path>{"o.png", "o.exr"}));
}

}  // namespace anamorph
