#include "render/checkpoint_records.h"

#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <cstring>

#include <fmt/format.h>

namespace anamorph::checkpoint_detail {

namespace fs = std::filesystem;

namespace {

uint32_t crc_of(const void* p, size_t n) {
  return uint32_t(crc32_z(crc32(0, nullptr, 0), static_cast<const Bytef*>(p), n));
}

// Payloads in the machine's byte order: a checkpoint continues on the machine (or cluster of
// alike machines) that started it.
template <class T>
void put(std::string& s, const T& v) {
  s.append(reinterpret_cast<const char*>(&v), sizeof v);
}
template <class T>
void put_vector(std::string& s, const std::vector<T>& v) {
  put(s, uint64_t(v.size()));
  s.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}
void put_string(std::string& s, const std::string& v) {
  put(s, uint64_t(v.size()));
  s += v;
}

// Reads what put() wrote; every count is checked against the bytes left before anything is
// allocated for it, and a record must be read to its last byte.
struct Cursor {
  const std::string& s;
  size_t at = 0;
  [[noreturn]] static void short_record() {
    throw CheckpointError("a record holds fewer bytes than its counts say");
  }
  template <class T>
  T get() {
    if (sizeof(T) > s.size() - at) short_record();
    T v;
    std::memcpy(&v, s.data() + at, sizeof v);
    at += sizeof v;
    return v;
  }
  template <class T>
  std::vector<T> get_vector() {
    const auto n = get<uint64_t>();
    if (n > (s.size() - at) / sizeof(T)) short_record();
    std::vector<T> v(n);
    if (n) std::memcpy(v.data(), s.data() + at, n * sizeof(T));  // (data() of none may be null)
    at += n * sizeof(T);
    return v;
  }
  std::string get_string() {
    const auto n = get<uint64_t>();
    if (n > s.size() - at) short_record();
    std::string v = s.substr(at, n);
    at += n;
    return v;
  }
  void end() const {
    if (at != s.size())
      throw CheckpointError(
          fmt::format("a record has {} bytes more than its counts say", s.size() - at));
  }
};

}  // namespace

std::string framed(uint32_t kind, const std::string& payload) {
  std::string r;
  put(r, kind);
  put(r, uint64_t(payload.size()));
  put(r, crc_of(payload.data(), payload.size()));
  put(r, crc_of(r.data(), r.size()));
  return r + payload;
}

RecordReader::RecordReader(int fd, const fs::path& file, uint64_t file_size, uint64_t at)
    : fd_(fd), file_(file), size_(file_size), at_(at) {}

void RecordReader::damaged(const std::string& why, bool last) const {
  throw CheckpointError(
      fmt::format("checkpoint '{}' is damaged at byte {} (record {}): {}; delete it to start over",
                  file_.string(), last ? last_ : at_, last ? records_ : records_ + 1, why));
}

bool RecordReader::read_at(uint64_t offset, void* p, size_t n) const {
  char* c = static_cast<char*>(p);
  while (n > 0) {
    const ssize_t r = ::pread(fd_, c, n, off_t(offset));
    if (r < 0 && errno == EINTR) continue;
    if (r < 0)
      throw CheckpointError(
          fmt::format("cannot read checkpoint '{}': {}", file_.string(), std::strerror(errno)));
    if (r == 0) return false;
    c += r, offset += uint64_t(r), n -= size_t(r);
  }
  return true;
}

// Whether every byte from `offset` to the end is zero: space a file system allocated for a
// write that never reached the disk (power lost after the size was updated).
bool RecordReader::zero_from(uint64_t offset) const {
  char buf[65536];
  while (offset < size_) {
    const size_t n = size_t(std::min<uint64_t>(sizeof buf, size_ - offset));
    if (!read_at(offset, buf, n)) return true;
    for (size_t i = 0; i < n; ++i)
      if (buf[i] != 0) return false;
    offset += n;
  }
  return true;
}

RecordReader::Next RecordReader::next(uint32_t* kind, std::string* payload) {
  if (at_ >= size_) return Next::End;
  if (size_ - at_ < kHeaderSize) return Next::Tail;  // a header cut short
  unsigned char h[kHeaderSize];
  if (!read_at(at_, h, kHeaderSize)) return Next::Tail;
  uint64_t size;
  uint32_t crc, header_crc;
  std::memcpy(kind, h, 4);
  std::memcpy(&size, h + 4, 8);
  std::memcpy(&crc, h + 12, 4);
  std::memcpy(&header_crc, h + 16, 4);
  if (header_crc != crc_of(h, 16)) {
    if (zero_from(at_)) return Next::Tail;
    damaged("its header does not match its checksum");
  }
  if (*kind < kIdentity || *kind > kPassStart) damaged(fmt::format("unknown kind {}", *kind));
  if (size > size_ - at_ - kHeaderSize) return Next::Tail;  // a record cut short
  payload->resize(size_t(size));
  if (!read_at(at_ + kHeaderSize, payload->data(), size_t(size))) return Next::Tail;
  if (crc_of(payload->data(), payload->size()) != crc)
    damaged("its data does not match its checksum");
  last_ = at_;
  at_ += kHeaderSize + size;
  ++records_;
  return Next::Record;
}

std::string encode_identity(const CheckpointIdentity& id) {
  std::string p;
  put(p, uint64_t(id.size()));
  for (const auto& [k, v] : id) put_string(p, k), put_string(p, v);
  return p;
}

CheckpointIdentity decode_identity(const std::string& payload) {
  Cursor c{payload};
  const auto n = c.get<uint64_t>();
  // (Each entry takes at least its two 8-byte lengths.)
  if (n > payload.size() / 16) Cursor::short_record();
  CheckpointIdentity id;
  for (uint64_t i = 0; i < n; ++i) {
    std::string k = c.get_string();
    id.emplace_back(std::move(k), c.get_string());
  }
  c.end();
  return id;
}

std::string encode_tile(const ResolvedTile& t) {
  std::string p;
  put(p, uint64_t(t.index));
  put(p, uint64_t(t.planes.size()));
  for (const Plane& plane : t.planes) put_vector(p, plane.u8), put_vector(p, plane.f32);
  return p;
}

ResolvedTile decode_tile(const std::string& payload) {
  Cursor c{payload};
  ResolvedTile t;
  t.index = size_t(c.get<uint64_t>());
  const auto planes = c.get<uint64_t>();
  if (planes > (payload.size() - c.at) / 16) Cursor::short_record();  // (two counts a plane)
  for (uint64_t i = 0; i < planes; ++i) {
    Plane& plane = t.planes.emplace_back();
    plane.u8 = c.get_vector<unsigned char>();
    plane.f32 = c.get_vector<float>();
  }
  c.end();
  return t;
}

std::string encode_pass_tile(int pass, size_t index, const TileBuffer& tile) {
  std::string p;
  put(p, int32_t(pass));
  put(p, uint64_t(index));
  put_vector(p, tile.sums());
  put_vector(p, tile.aov_sums());
  return p;
}

PassTile decode_pass_tile(const std::string& payload) {
  Cursor c{payload};
  PassTile t;
  t.pass = c.get<int32_t>();
  t.index = size_t(c.get<uint64_t>());
  t.sums = c.get_vector<PixelSum>();
  t.aov = c.get_vector<float>();
  c.end();
  if (t.pass < 0) throw CheckpointError(fmt::format("a tile of pass {}", t.pass));
  return t;
}

std::string encode_pass_start(int pass, const std::vector<uint8_t>& active) {
  std::string p;
  put(p, int32_t(pass));
  put_vector(p, active);
  return p;
}

std::pair<int, std::vector<uint8_t>> decode_pass_start(const std::string& payload) {
  Cursor c{payload};
  const int pass = c.get<int32_t>();
  std::vector<uint8_t> active = c.get_vector<uint8_t>();
  c.end();
  if (pass < 0) throw CheckpointError(fmt::format("the start of pass {}", pass));
  return {pass, std::move(active)};
}

}  // namespace anamorph::checkpoint_detail
