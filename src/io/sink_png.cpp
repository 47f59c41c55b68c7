// The PNG sink: the beauty as 8-bit sRGB RGBA with straight alpha (io/image_stream.h, PngStream).
// Each strip is filtered and deflated as a band of its own on the thread that completes it, and
// the bands are appended in order; the other layers go to a file of a kind that takes them.
#include <any>

#include "io/image_sink.h"
#include "io/image_stream.h"

namespace anamorph {

namespace {

class PngSink final : public ImageSink {
 public:
  explicit PngSink(const SinkSpec& s) : png_(s.file, s.width, s.height, s.metadata) {}
  // (A member, not a function's static: a thread may write while the process exits.)
  const std::vector<LayerRequest>& requests() const override { return requests_; }
  void prepare(Strip& s) const override {
    s.prepared = PngStream::encode(s.planes[0].u8.data(), png_.width(), s.rows);
    s.planes[0].u8 = {};  // (the band is what append() writes)
  }
  void append(const Strip& s) override {
    png_.append(*std::any_cast<PngStream::Band>(&s.prepared), s.rows);
  }
  void commit() override { png_.commit(); }
  void commit_as(const std::filesystem::path& as) override { png_.commit_as(as); }

 private:
  std::vector<LayerRequest> requests_{{"", Encoding::Srgb8}};
  PngStream png_;
};

}  // namespace

extern const SinkKind kPngSink;
const SinkKind kPngSink{
    "png",
    {".png"},
    [](const std::vector<LayerSpec>&) {
      return std::vector<LayerRequest>{{"", Encoding::Srgb8}};
    },
    [](const SinkSpec& s) -> std::unique_ptr<ImageSink> { return std::make_unique<PngSink>(s); },
    2,
    "image/png",
    "PNG (8-bit sRGB)"};

}  // namespace anamorph
