// The messages between MPI ranks (dist/wire.h): the first byte picks what the bytes after it are
// read as (a tile handed out, or the result of a pass tile, a whole tile or a resolved tile),
// and a message that does not fit is refused with std::runtime_error, never read past its end
// or outside a tile. Ranks are one job's processes, not strangers; the decoders still check
// everything, and this keeps them honest.
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "dist/wire.h"

using namespace anamorph;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1 || size > (1 << 20)) return 0;
  const auto* bytes = reinterpret_cast<const char*>(data + 1);
  const size_t n = size - 1;
  try {
    if (data[0] % 4 == 0) {
      dist::WorkMessage m = dist::decode_work(bytes, n);
      // A worker puts a pass tile's sums in place only for a tile inside its image.
      if (!m.whole && m.rect.pixels() <= 64 * 64) {
        TileBuffer t(m.rect, {Aov::Albedo});
        dist::unpack_work(m, t);
      }
      return 0;
    }
    // A result for the tile the head handed out: 4 x 4 pixels at (8, 4), one AOV layer.
    TileBuffer head(TileRect{8, 4, 12, 8}, {Aov::Albedo});
    std::vector<uint8_t> active(20 * 10, 1);
    for (size_t i = 0; i < active.size(); i += 3) active[i] = 0;
    FarmTile sent;
    sent.index = 5;
    sent.rect = head.rect();
    sent.image_width = 20;
    sent.whole = data[0] % 4 != 1;
    // (what a PNG and an EXR of the render take)
    const std::vector<LayerRequest> plan{
        {"", Encoding::Srgb8}, {"", Encoding::Float32}, {"albedo", Encoding::Float32}};
    if (data[0] % 4 == 3) sent.plan = &plan;
    sent.sums = &head;
    sent.range.active = &active;
    const std::vector<uint8_t> mask =
        sent.whole ? std::vector<uint8_t>() : dist::mask_slice(&active, 20, sent.rect);
    dist::decode_result(bytes, n, {Aov::Albedo}, sent, mask);
  } catch (const std::runtime_error&) {
  }
  return 0;
}
