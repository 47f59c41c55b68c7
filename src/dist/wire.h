// The messages between the head rank and the workers, as bytes: a tile handed out and a tile
// given back. Plain C++ (no MPI) so they are tested without mpirun. Both ends are the same build
// on machines of one architecture (an MPI job), so numbers travel in native byte order.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "render/tile_farm.h"

namespace anamorph::dist {

// Message tags.
enum Tag : int {
  kReady = 1,   // worker -> head: how many tiles it takes at once (u32)
  kFrame = 2,   // head -> worker: load this frame (f64) before its tiles arrive
  kWork = 3,    // head -> worker: a tile to render
  kResult = 4,  // worker -> head: a rendered tile
  kError = 5,   // worker -> head: a message; the job cannot go on
  kStop = 6,    // head -> worker: no more work
};

class WireWriter {
 public:
  template <class T>
  void put(const T& v) {
    const auto* p = reinterpret_cast<const char*>(&v);
    bytes_.insert(bytes_.end(), p, p + sizeof(T));
  }
  template <class T>
  void put_array(const T* p, size_t n) {
    put(uint64_t(n));
    const auto* b = reinterpret_cast<const char*>(p);
    if (n) bytes_.insert(bytes_.end(), b, b + n * sizeof(T));
  }
  std::vector<char>& bytes() { return bytes_; }

 private:
  std::vector<char> bytes_;
};

class WireReader {
 public:
  WireReader(const char* data, size_t size) : p_(data), end_(data + size) {}
  template <class T>
  T get() {
    T v;
    need(sizeof(T));
    std::memcpy(&v, p_, sizeof(T));
    p_ += sizeof(T);
    return v;
  }
  template <class T>
  void get_array(std::vector<T>& out) {
    const auto n = get<uint64_t>();
    if (n > size_t(end_ - p_) / sizeof(T)) throw std::runtime_error("message too short");
    out.resize(n);
    if (n) std::memcpy(out.data(), p_, n * sizeof(T));
    p_ += n * sizeof(T);
  }
  bool done() const { return p_ == end_; }

 private:
  void need(size_t n) const {
    if (size_t(end_ - p_) < n) throw std::runtime_error("message too short");
  }
  const char* p_;
  const char* end_;
};

// A tile as the head hands it out. A pass of a pass render moves only the pixels that take
// samples in it (those its part of the active mask leaves on, or all without a mask), and their
// sums so far only after the first pass: after a few passes of per-pixel adaptive sampling most
// pixels have stopped, and the traffic shrinks with them.
struct WorkMessage {
  size_t index = 0;
  TileRect rect;
  bool whole = true;
  // A whole tile resolved where rendered to `plan` (FarmTile::plan), else its sums come back.
  bool resolve = false;
  std::vector<LayerRequest> plan;
  uint32_t begin = 0, end = 0;
  double footprint = 1;
  std::vector<uint8_t> active;  // the rect's part of the mask, row by row (empty: all pixels on)
  std::vector<PixelSum> sums;   // the sampled pixels' sums so far, in order (empty: all zero)
  std::vector<float> aov;
};

// The tile's part of a frame-wide mask, row by row (empty when `active` is null).
std::vector<uint8_t> mask_slice(const std::vector<uint8_t>* active, int image_width,
                                const TileRect& rect);

// `mask`: the tile's part of the pass's mask (mask_slice), kept by the head to read the result.
std::vector<char> encode_work(const FarmTile& t, const std::vector<uint8_t>& mask);
WorkMessage decode_work(const char* data, size_t size);
// The worker's buffer for a pass: zero, with the sampled pixels' sums so far in place.
void unpack_work(WorkMessage& m, TileBuffer& tile);

// A rendered tile on its way back: a whole tile every pixel, a pass the pixels `mask` leaves on
// (empty: all).
std::vector<char> encode_result(size_t index, const TileBuffer& tile, bool whole,
                                const std::vector<uint8_t>& mask, const TileStats& st,
                                double seconds);
// A whole tile resolved where it was rendered: each plane of its plan.
std::vector<char> encode_resolved(const ResolvedTile& tile, const TileRect& rect,
                                  const TileStats& st, double seconds);
// The result of tile `sent` (as the head handed it out): a whole tile into a new buffer with the
// head's AOVs, or resolved to `sent.plan` (each plane as many values as the layer and encoding
// take); a pass into `sent.sums` (the head's tile), of which the message carries the pixels
// `mask` leaves on. Throws when it does not fit what was sent.
FarmResult decode_result(const char* data, size_t size, const std::vector<Aov>& aovs,
                         const FarmTile& sent, const std::vector<uint8_t>& mask = {});
// The tile index a result is for.
size_t result_index(const char* data, size_t size);

}  // namespace anamorph::dist
