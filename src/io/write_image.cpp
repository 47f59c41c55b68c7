// A whole image in memory written through the sink its file name chooses: cut into strips of 64
// rows, each strip's planes made from the image's float layers, prepared in parallel (a PNG's
// bands are deflated at once, a batch of strips at a time) and appended in order. For a PNG
// these are the bytes write_png gives (the same 64-row bands).
#include <fmt/format.h>
#include <tbb/task_arena.h>

#include <algorithm>

#include "io/image_io.h"
#include "io/image_sink.h"
#include "io/io_util.h"
#include "math/parallel.h"

namespace anamorph {

namespace fs = std::filesystem;

namespace {

constexpr int kStripRows = 64;

const ImageLayer& layer_named(const OutputImage& img, const std::string& name,
                              const fs::path& file) {
  for (const ImageLayer& l : img.layers)
    if (l.name == name) return l;
  io_detail::fail("cannot write image", file,
                  fmt::format("its format needs a layer '{}' the image does not have", name));
}

// Rows [y0, y0 + rows) of `layer` in `encoding`.
Plane plane_of(const ImageLayer& layer, Encoding encoding, int width, int y0, int rows,
               const fs::path& file) {
  Plane p;
  const size_t nc = layer.channels.size(), first = size_t(y0) * size_t(width),
               n = size_t(rows) * size_t(width);
  if (encoding == Encoding::Float32) {
    p.f32.assign(layer.data.begin() + ptrdiff_t(first * nc),
                 layer.data.begin() + ptrdiff_t((first + n) * nc));
    return p;
  }
  if (nc != 3 && nc != 4)
    io_detail::fail("cannot write image", file,
                    fmt::format("8-bit colour needs an RGB or RGBA layer, '{}' has {} channels",
                                layer.name, nc));
  // Straight colour, sRGB-encoded; alpha is linear coverage (1 when absent).
  p.u8.resize(n * 4);
  for (size_t i = 0; i < n; ++i) {
    const float* src = &layer.data[(first + i) * nc];
    const float px[4] = {src[0], src[1], src[2], nc == 4 ? src[3] : 1.0f};
    encode_rgba8(px, &p.u8[i * 4]);
  }
  return p;
}

}  // namespace

void write_image(const fs::path& file, const OutputImage& img) {
  const SinkKind& kind = sink_kind(file);
  io_detail::check_output(img, file);
  SinkSpec spec{file, img.width, img.height, {}, img.metadata};
  for (const ImageLayer& l : img.layers) spec.layers.push_back({l.name, l.channels});
  const std::unique_ptr<ImageSink> sink = kind.make(spec);
  // A few strips a thread at a time: at most that many copies of the image's rows in flight.
  const int strips = (img.height + kStripRows - 1) / kStripRows,
            batch = 2 * std::max(1, tbb::this_task_arena::max_concurrency());
  for (int first = 0; first < strips; first += batch) {
    std::vector<Strip> ready(size_t(std::min(batch, strips - first)));
    parallel_for_each(0, int(ready.size()), [&](int i) {
      Strip& strip = ready[size_t(i)];
      const int y0 = (first + i) * kStripRows;
      strip.rows = std::min(kStripRows, img.height - y0);
      for (const LayerRequest& r : sink->requests())
        strip.planes.push_back(
            plane_of(layer_named(img, r.layer, file), r.encoding, img.width, y0, strip.rows, file));
      sink->prepare(strip);
    });
    for (const Strip& s : ready) sink->append(s);
  }
  sink->commit();
}

}  // namespace anamorph
