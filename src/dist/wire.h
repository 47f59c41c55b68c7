// The messages between the head rank and the workers, as bytes: a tile handed out and a tile
// given back. Plain C++ (no MPI) so they are tested without mpirun. Both ends are the same build
// on machines of one architecture (an MPI job), so numbers travel in native byte order.
#pragma once

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

// A tile as the head hands it out: which one, its rectangle, and for a pass its sums so far and
// its part of the active mask.
struct WorkMessage {
  size_t index = 0;
  TileRect rect;
  bool whole = true;
  uint32_t begin = 0, end = 0;
  double footprint = 1;
  std::vector<PixelSum> sums;
  std::vector<float> aov;
  std::vector<uint8_t> active;  // the rect's pixels, row by row (empty: all on)
};

std::vector<char> encode_work(const FarmTile& t);
WorkMessage decode_work(const char* data, size_t size);

// A rendered tile on its way back.
std::vector<char> encode_result(size_t index, const TileBuffer& tile, const TileStats& st,
                                double seconds);
// Into a buffer of the tile's rectangle with the head's AOVs.
FarmResult decode_result(const char* data, size_t size, const std::vector<Aov>& aovs);

}  // namespace anamorph::dist
