#include "app/warp_frame.h"

#include <signal.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <memory>
#include <vector>

#include "app/interrupt.h"
#include "io/image_io.h"
#include "io/image_sink.h"
#include "math/parallel.h"

namespace anamorph::app {

namespace fs = std::filesystem;

namespace {

constexpr int kStripRows = 64;

// The strip of rows [y0, y0 + rows) of `rgba` (the batch's rows from `batch_y0`) in the planes
// the sink asks for.
Strip strip_of(const ImageSink& sink, const std::vector<float>& rgba, int width, int batch_y0,
               int y0, int rows) {
  Strip s;
  s.rows = rows;
  const size_t n = size_t(rows) * size_t(width);
  const float* first = rgba.data() + size_t(y0 - batch_y0) * size_t(width) * 4;
  for (const LayerRequest& r : sink.requests()) {
    Plane p;
    if (r.encoding == Encoding::Float32) {
      p.f32.assign(first, first + n * 4);
    } else {
      p.u8.resize(n * 4);
      for (int y = 0; y < rows; ++y)
        encode_rgba8(first + size_t(y) * size_t(width) * 4, size_t(width),
                     &p.u8[size_t(y) * size_t(width) * 4]);
    }
    s.planes.push_back(std::move(p));
  }
  return s;
}

}  // namespace

void warp_to_file(const WarpView& v, const fs::path& file,
                  const std::map<std::string, std::string>& metadata,
                  const std::function<void(double)>& progress,
                  const std::function<void()>& committed) {
  SinkSpec spec{file, v.width, v.height, {{"", {"R", "G", "B", "A"}}}, metadata};
  const std::unique_ptr<ImageSink> sink = make_file_sink(spec);
  // A batch: two strips a thread, computed a row at a time in parallel, then each strip
  // prepared (a PNG band deflated) in parallel and appended in order.
  const int per_batch = 2 * std::max(1, tbb::this_task_arena::max_concurrency()) * kStripRows;
  std::vector<float> rgba;
  for (int y0 = 0; y0 < v.height; y0 += per_batch) {
    const int rows = std::min(per_batch, v.height - y0);
    rgba.resize(size_t(rows) * size_t(v.width) * 4);
    parallel_for_each(
        0, rows, [&](int r) { warp_rows(v, y0 + r, 1, &rgba[size_t(r) * size_t(v.width) * 4]); });
    std::vector<Strip> strips(size_t((rows + kStripRows - 1) / kStripRows));
    parallel_for_each(0, int(strips.size()), [&](int i) {
      const int sy = y0 + i * kStripRows;
      strips[size_t(i)] =
          strip_of(*sink, rgba, v.width, y0, sy, std::min(kStripRows, y0 + rows - sy));
      sink->prepare(strips[size_t(i)]);
    });
    for (const Strip& s : strips) sink->append(s);
    if (progress) progress(double(y0 + rows) / v.height);
  }
  {  // A stop signal during the commit waits for it and the note that says it was written.
    const RenderPhase hold;
    sink->commit();
    if (committed) committed();
  }
  if (interrupt_flag()) ::raise(SIGINT);  // (the handler: the note, exit 3)
}

}  // namespace anamorph::app
