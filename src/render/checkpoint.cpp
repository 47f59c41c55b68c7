#include "render/checkpoint.h"

#include <fcntl.h>
#include <toml++/toml.h>
#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <cstring>
#include <map>
#include <sstream>
#include <system_error>
#include <variant>

#include <fmt/format.h>

#include "io/image_io.h"
#include "io/read_file.h"

namespace anamorph {

namespace fs = std::filesystem;

namespace {

constexpr char kSignature[16] = {'A', 'N', 'A', 'M', 'O', 'R', 'P', 'H',
                                 '-', 'C', 'K', 'P', 'T', '-', '1', '\n'};
enum Kind : uint32_t { kIdentity = 1, kTile = 2, kPassTile = 3, kPassStart = 4 };
// A record larger than this is damage, not data (a 16384^2 frame's tile row is far smaller).
constexpr uint64_t kMaxRecord = uint64_t(1) << 34;

std::string sys_error() { return std::generic_category().message(errno); }

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

// Reads what put() wrote; throws CheckpointError when the payload is short.
struct Cursor {
  const std::string& s;
  size_t at = 0;
  void need(size_t n) const {
    if (n > s.size() - at) throw CheckpointError("a checkpoint record is shorter than it says");
  }
  template <class T>
  T get() {
    need(sizeof(T));
    T v;
    std::memcpy(&v, s.data() + at, sizeof v);
    at += sizeof v;
    return v;
  }
  template <class T>
  std::vector<T> get_vector() {
    const auto n = get<uint64_t>();
    if (n > (s.size() - at) / sizeof(T)) need(s.size() + 1);
    std::vector<T> v(n);
    if (n) std::memcpy(v.data(), s.data() + at, n * sizeof(T));  // (data() of none may be null)
    at += n * sizeof(T);
    return v;
  }
  std::string get_string() {
    const auto n = get<uint64_t>();
    need(n);
    std::string v = s.substr(at, n);
    at += n;
    return v;
  }
};

void write_all(int fd, const void* p, size_t n, const fs::path& file) {
  const char* c = static_cast<const char*>(p);
  while (n > 0) {
    const ssize_t w = ::write(fd, c, n);
    if (w < 0 && errno == EINTR) continue;
    if (w < 0)
      throw CheckpointError(
          fmt::format("cannot write checkpoint '{}': {}", file.string(), sys_error()));
    c += w;
    n -= size_t(w);
  }
}

bool read_all(int fd, void* p, size_t n) {
  char* c = static_cast<char*>(p);
  while (n > 0) {
    const ssize_t r = ::read(fd, c, n);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return false;
    c += r;
    n -= size_t(r);
  }
  return true;
}

std::string framed(uint32_t kind, const std::string& payload) {
  std::string r;
  put(r, kind);
  put(r, uint32_t(crc32_z(crc32(0, nullptr, 0), reinterpret_cast<const Bytef*>(payload.data()),
                          payload.size())));
  put(r, uint64_t(payload.size()));
  return r + payload;
}

void flatten(const toml::node& n, const std::string& key, CheckpointIdentity& out) {
  if (const toml::table* t = n.as_table()) {
    for (const auto& [k, v] : *t)
      flatten(v, key.empty() ? std::string(k.str()) : key + "." + std::string(k.str()), out);
    return;
  }
  if (const toml::array* a = n.as_array(); a && !a->empty() && a->is_array_of_tables()) {
    for (size_t i = 0; i < a->size(); ++i) flatten(*a->get(i), key + "." + std::to_string(i), out);
    return;
  }
  std::ostringstream text;
  n.visit([&text](const auto& v) { text << v; });
  out.emplace_back(key, text.str());
}

}  // namespace

CheckpointIdentity flatten_toml(const std::string& toml_text, const std::string& prefix) {
  CheckpointIdentity out;
  flatten(toml::parse(toml_text), prefix, out);
  return out;
}

std::string identity_changes(const CheckpointIdentity& saved, const CheckpointIdentity& now) {
  std::map<std::string, std::string> a(saved.begin(), saved.end()), b(now.begin(), now.end());
  a.erase("command"), b.erase("command");  // how the render was started: kept, not compared
  std::vector<std::string> changes;
  const auto shown = [](const std::string& v) { return v.size() <= 40 && v.find('\n') == v.npos; };
  for (const auto& [k, v] : a) {
    const auto it = b.find(k);
    if (it == b.end())
      changes.push_back(k + (shown(v) ? " (was " + v + ") is gone" : " is gone"));
    else if (it->second != v)
      changes.push_back(shown(v) && shown(it->second)
                            ? fmt::format("{} was {}, is {}", k, v, it->second)
                            : k + " changed");
  }
  for (const auto& [k, v] : b)
    if (!a.count(k)) changes.push_back(k + (shown(v) ? " = " + v + " is new" : " is new"));
  std::string msg;
  for (size_t i = 0; i < changes.size() && i < 6; ++i) msg += (i ? "; " : "") + changes[i];
  if (changes.size() > 6) msg += fmt::format("; and {} more", changes.size() - 6);
  return msg;
}

CheckpointWriter::CheckpointWriter(const fs::path& file, const CheckpointIdentity& id,
                                   double sync_every, uint64_t append_at)
    : file_(file), every_(sync_every), last_sync_(std::chrono::steady_clock::now()) {
  put(identity_payload_, uint64_t(id.size()));
  for (const auto& [k, v] : id) put_string(identity_payload_, k), put_string(identity_payload_, v);
  if (append_at == 0) {
    restart();
    return;
  }
  open_append();
  if (::ftruncate(fd_, off_t(append_at)) != 0)
    throw CheckpointError(
        fmt::format("cannot continue checkpoint '{}': {}", file.string(), sys_error()));
}

CheckpointWriter::~CheckpointWriter() {
  if (fd_ < 0) return;
  ::fsync(fd_);
  ::close(fd_);
}

void CheckpointWriter::open_append() {
  fd_ = ::open(file_.c_str(), O_WRONLY | O_APPEND | O_CLOEXEC);
  if (fd_ < 0)
    throw CheckpointError(
        fmt::format("cannot open checkpoint '{}': {}", file_.string(), sys_error()));
}

void CheckpointWriter::restart() {
  const std::lock_guard<std::mutex> lock(mu_);
  if (fd_ >= 0) ::close(fd_), fd_ = -1;
  const std::string head = std::string(kSignature, 16) + framed(kIdentity, identity_payload_);
  try {
    write_file_atomic(file_, head.data(), head.size());
  } catch (const ImageIoError& e) {
    throw CheckpointError(e.what());
  }
  open_append();
}

void CheckpointWriter::record(uint32_t kind, const std::string& payload) {
  const std::string r = framed(kind, payload);
  const std::lock_guard<std::mutex> lock(mu_);
  write_all(fd_, r.data(), r.size(), file_);  // O_APPEND: one write per record
  const auto now = std::chrono::steady_clock::now();
  if (std::chrono::duration<double>(now - last_sync_).count() >= every_) {
    ::fsync(fd_);
    last_sync_ = now;
  }
}

void CheckpointWriter::sync() {
  const std::lock_guard<std::mutex> lock(mu_);
  if (fd_ >= 0) ::fsync(fd_);
}

void CheckpointWriter::add_tile(const ResolvedTile& t) {
  std::string p;
  put(p, uint64_t(t.index));
  put(p, uint64_t(t.planes.size()));
  for (const Plane& plane : t.planes) put_vector(p, plane.u8), put_vector(p, plane.f32);
  record(kTile, p);
}

void CheckpointWriter::add_pass_tile(int pass, size_t index, const TileBuffer& tile) {
  std::string p;
  put(p, int32_t(pass));
  put(p, uint64_t(index));
  put_vector(p, tile.sums());
  put_vector(p, tile.aov_sums());
  record(kPassTile, p);
}

void CheckpointWriter::add_pass_start(int pass, const std::vector<uint8_t>& active) {
  std::string p;
  put(p, int32_t(pass));
  put_vector(p, active);
  record(kPassStart, p);
}

CheckpointReader::CheckpointReader(const fs::path& file) : file_(file) {
  // (read record by record, so no size limit; a FIFO or device is refused: io/read_file.h)
  auto opened = open_input(file, InputKind{"a checkpoint", UINT64_MAX});
  if (const auto* f = std::get_if<ReadFailure>(&opened))
    throw CheckpointError(fmt::format("cannot read checkpoint '{}': {}", file.string(), f->reason));
  fd_ = std::get<InputFile>(opened).release();
  char sig[16];
  uint32_t kind = 0;
  std::string payload;
  if (!read_all(fd_, sig, 16) || std::memcmp(sig, kSignature, 16) != 0)
    throw CheckpointError(fmt::format("'{}' is not an anamorph checkpoint", file.string()));
  end_ = 16;
  if (!next(&kind, &payload) || kind != kIdentity)
    throw CheckpointError(
        fmt::format("checkpoint '{}' is damaged: no identity record", file.string()));
  Cursor c{payload};
  const auto n = c.get<uint64_t>();
  for (uint64_t i = 0; i < n; ++i) {
    std::string k = c.get_string();
    id_.emplace_back(std::move(k), c.get_string());
  }
}

CheckpointReader::~CheckpointReader() {
  if (fd_ >= 0) ::close(fd_);
}

bool CheckpointReader::next(uint32_t* kind, std::string* payload) {
  char head[16];
  if (!read_all(fd_, head, 16)) return false;
  uint32_t crc;
  uint64_t size;
  std::memcpy(kind, head, 4);
  std::memcpy(&crc, head + 4, 4);
  std::memcpy(&size, head + 8, 8);
  if (size > kMaxRecord) return false;
  payload->resize(size);
  if (!read_all(fd_, payload->data(), size)) return false;
  if (crc32_z(crc32(0, nullptr, 0), reinterpret_cast<const Bytef*>(payload->data()), size) != crc)
    return false;
  end_ += 16 + size;
  return true;
}

void CheckpointReader::read(const Visitor& v) {
  uint32_t kind = 0;
  std::string payload;
  while (next(&kind, &payload)) {
    Cursor c{payload};
    if (kind == kTile && v.tile) {
      ResolvedTile t;
      t.index = c.get<uint64_t>();
      const auto planes = c.get<uint64_t>();
      if (planes > payload.size() / 16)  // (two counts a plane at least)
        throw CheckpointError("a checkpoint record is shorter than it says");
      for (uint64_t i = 0; i < planes; ++i) {
        Plane& plane = t.planes.emplace_back();
        plane.u8 = c.get_vector<unsigned char>();
        plane.f32 = c.get_vector<float>();
      }
      v.tile(std::move(t));
    } else if (kind == kPassTile && v.pass_tile) {
      PassTile t;
      t.pass = c.get<int32_t>();
      t.index = c.get<uint64_t>();
      t.sums = c.get_vector<PixelSum>();
      t.aov = c.get_vector<float>();
      v.pass_tile(std::move(t));
    } else if (kind == kPassStart && v.pass_start) {
      const int pass = c.get<int32_t>();
      v.pass_start(pass, c.get_vector<uint8_t>());
    }
  }
}

}  // namespace anamorph
