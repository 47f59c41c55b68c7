// The Middlebury .flo sink (Baker et al., "A Database and Evaluation Methodology for Optical
// Flow", and OpenCV's readOpticalFlow/writeOpticalFlow): the float 202021.25 ("PIEH" in little
// endian), the width and height as 32-bit integers, then (u, v) as 32-bit floats per pixel,
// row-major from the top row. It holds one flow layer of the render (x right, y down, pixels):
// flow_forward, or flow_backward when the render has no flow_forward; a pixel without flow (NaN
// in the EXR) holds 1e10, the format's "unknown flow" (its readers treat values above 1e9 so).
// Little-endian hosts only, like the rest of anamorph's writers.
#include <any>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "io/image_io.h"
#include "io/image_sink.h"

namespace anamorph {

namespace {

constexpr float kUnknownFlow = 1e10f;

// The flow layer a .flo file holds of a render with `layers`, or none.
std::vector<LayerRequest> flow_layer(const std::vector<LayerSpec>& layers) {
  for (const char* name : {"flow_forward", "flow_backward"})
    for (const LayerSpec& l : layers)
      if (l.name == name) return {{l.name, Encoding::Float32}};
  return {};
}

class FloSink final : public ImageSink {
 public:
  explicit FloSink(const SinkSpec& s)
      : requests_(flow_layer(s.layers)), width_(s.width), file_(s.file) {
    if (requests_.empty())
      throw ImageIoError("cannot write image '" + s.file.string() +
                         "': a .flo file holds flow_forward or flow_backward, and the render has "
                         "neither (add --aov flow_forward)");
    const float tag = 202021.25f;
    const int32_t size[2] = {s.width, s.height};
    file_.write(&tag, 4);
    file_.write(size, 8);
  }
  const std::vector<LayerRequest>& requests() const override { return requests_; }
  void prepare(Strip& s) const override {
    // (X, Y, valid) a pixel -> (u, v).
    const std::vector<float>& f = s.planes[0].f32;
    std::vector<float> uv(size_t(width_) * size_t(s.rows) * 2);
    for (size_t i = 0; i < uv.size() / 2; ++i)
      for (size_t c = 0; c < 2; ++c)
        uv[2 * i + c] = std::isnan(f[3 * i + c]) ? kUnknownFlow : f[3 * i + c];
    s.prepared = std::move(uv);
    s.planes[0].f32 = {};
  }
  void append(const Strip& s) override {
    const auto& uv = *std::any_cast<std::vector<float>>(&s.prepared);
    file_.write(uv.data(), uv.size() * sizeof(float));
  }
  void commit() override { file_.commit(); }
  void commit_as(const std::filesystem::path& as) override { file_.commit_as(as); }

 private:
  const std::vector<LayerRequest> requests_;
  int width_;
  AtomicFile file_;
};

}  // namespace

extern const SinkKind kFloSink;
const SinkKind kFloSink{
    "flo",
    {".flo"},
    flow_layer,
    [](const SinkSpec& s) -> std::unique_ptr<ImageSink> { return std::make_unique<FloSink>(s); },
    2,
    "application/octet-stream",
    "Middlebury optical flow (flow_forward, else flow_backward)"};

}  // namespace anamorph
