// The EXR sink: every layer as 32-bit float channels ("R", "albedo.R", ...), ZIP-compressed
// scanlines appended as strips arrive (io/image_stream.h, ExrStream over OpenEXR, whose thread
// pool compresses a strip's chunks in parallel).
#include "io/image_sink.h"
#include "io/image_stream.h"

namespace anamorph {

namespace {

std::vector<LayerRequest> every_layer(const std::vector<LayerSpec>& layers) {
  std::vector<LayerRequest> r;
  for (const LayerSpec& l : layers) r.push_back({l.name, Encoding::Float32});
  return r;
}

class ExrSink final : public ImageSink {
 public:
  explicit ExrSink(const SinkSpec& s)
      : requests_(every_layer(s.layers)), exr_(s.file, s.width, s.height, s.layers, s.metadata) {}
  const std::vector<LayerRequest>& requests() const override { return requests_; }
  void prepare(Strip&) const override {}  // (OpenEXR compresses in append())
  void append(const Strip& s) override {
    std::vector<const float*> layers;
    for (const Plane& p : s.planes) layers.push_back(p.f32.data());
    exr_.write_rows(layers, s.rows);
  }
  void commit() override { exr_.commit(); }
  void commit_as(const std::filesystem::path& as) override { exr_.commit_as(as); }

 private:
  const std::vector<LayerRequest> requests_;
  ExrStream exr_;
};

}  // namespace

extern const SinkKind kExrSink;
const SinkKind kExrSink{
    "exr",
    {".exr"},
    every_layer,
    [](const SinkSpec& s) -> std::unique_ptr<ImageSink> { return std::make_unique<ExrSink>(s); },
    1,
    "image/x-exr",
    "OpenEXR (float, every layer)"};

}  // namespace anamorph
