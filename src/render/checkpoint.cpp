#include "render/checkpoint.h"

#include <fcntl.h>
#include <toml++/toml.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <map>
#include <sstream>
#include <system_error>
#include <variant>

#include <fmt/format.h>

#include "io/image_io.h"
#include "io/read_file.h"
#include "render/checkpoint_records.h"

namespace anamorph {

namespace fs = std::filesystem;

using namespace checkpoint_detail;

namespace {

std::string sys_error() { return std::generic_category().message(errno); }

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
    : file_(file),
      identity_payload_(encode_identity(id)),
      every_(sync_every),
      last_sync_(std::chrono::steady_clock::now()) {
  if (append_at == 0) {
    begin_rewrite();
    commit_rewrite();
    return;
  }
  open_append();
  if (::ftruncate(fd_, off_t(append_at)) != 0)
    throw CheckpointError(
        fmt::format("cannot continue checkpoint '{}': {}", file.string(), sys_error()));
}

CheckpointWriter::~CheckpointWriter() {
  rewrite_.reset();  // (an unfinished rewrite is dropped: the old log stays)
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

void CheckpointWriter::begin_rewrite() {
  const std::lock_guard<std::mutex> lock(mu_);
  const std::string head =
      std::string(kSignature, kSignatureSize) + framed(kIdentity, identity_payload_);
  try {
    rewrite_ = std::make_unique<AtomicFile>(file_);
    rewrite_->write(head.data(), head.size());
  } catch (const ImageIoError& e) {
    rewrite_.reset();
    throw CheckpointError(e.what());
  }
}

void CheckpointWriter::commit_rewrite() {
  const std::lock_guard<std::mutex> lock(mu_);
  if (!rewrite_) return;
  try {
    rewrite_->commit();  // fsync, rename over the old log, fsync the directory
  } catch (const ImageIoError& e) {
    rewrite_.reset();
    throw CheckpointError(e.what());
  }
  rewrite_.reset();
  if (fd_ >= 0) ::close(fd_), fd_ = -1;
  open_append();
  last_sync_ = std::chrono::steady_clock::now();
}

void CheckpointWriter::record(uint32_t kind, const std::string& payload) {
  const std::string r = framed(kind, payload);
  const std::lock_guard<std::mutex> lock(mu_);
  if (rewrite_) {
    try {
      rewrite_->write(r.data(), r.size());
    } catch (const ImageIoError& e) {
      throw CheckpointError(e.what());
    }
    return;
  }
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

void CheckpointWriter::add_tile(const ResolvedTile& t) { record(kTile, encode_tile(t)); }

void CheckpointWriter::add_pass_tile(int pass, size_t index, const TileBuffer& tile) {
  record(kPassTile, encode_pass_tile(pass, index, tile));
}

void CheckpointWriter::add_pass_start(int pass, const std::vector<uint8_t>& active) {
  record(kPassStart, encode_pass_start(pass, active));
}

namespace {

constexpr char kSignatureV1[kSignatureSize] = {'A', 'N', 'A', 'M', 'O', 'R', 'P', 'H',
                                               '-', 'C', 'K', 'P', 'T', '-', '1', '\n'};

// Decodes a record's payload (to check it: the data is dropped), naming the record when it
// does not hold what its kind says.
template <class Decode>
auto decoded(RecordReader& rr, Decode&& decode, const std::string& payload) {
  try {
    return decode(payload);
  } catch (const CheckpointError& e) {
    rr.damaged(e.what(), /*last=*/true);
  }
}

}  // namespace

CheckpointReader::CheckpointReader(const fs::path& file) : file_(file) {
  // (Read record by record, so no size limit; a FIFO or a device is refused: io/read_file.h.)
  auto opened = open_input(file, InputKind{"a checkpoint", UINT64_MAX});
  if (const auto* f = std::get_if<ReadFailure>(&opened))
    throw CheckpointError(fmt::format("cannot read checkpoint '{}': {}", file.string(), f->reason));
  const uint64_t size = std::get<InputFile>(opened).size();
  fd_ = std::get<InputFile>(opened).release();
  try {
    scan(size);
  } catch (...) {
    ::close(fd_);
    fd_ = -1;
    throw;
  }
}

void CheckpointReader::scan(uint64_t file_size) {
  char sig[kSignatureSize] = {};
  const bool whole = ::pread(fd_, sig, kSignatureSize, 0) == ssize_t(kSignatureSize);
  if (whole && std::memcmp(sig, kSignatureV1, kSignatureSize) == 0)
    throw CheckpointError(fmt::format(
        "checkpoint '{}' was written by an earlier anamorph (checkpoint format 1), which this "
        "version does not resume: finish it with that version, or delete it to start over",
        file_.string()));
  if (!whole || std::memcmp(sig, kSignature, kSignatureSize) != 0)
    throw CheckpointError(fmt::format("'{}' is not an anamorph checkpoint", file_.string()));
  RecordReader rr(fd_, file_, file_size, kSignatureSize);
  uint32_t kind = 0;
  std::string payload;
  if (rr.next(&kind, &payload) != RecordReader::Next::Record || kind != kIdentity)
    rr.damaged("the file does not begin with the render's identity", true);
  id_ = decoded(rr, decode_identity, payload);
  body_ = rr.at();
  int tiles = 0, pass_tiles = 0, pass_starts = 0;
  RecordReader::Next n;
  while ((n = rr.next(&kind, &payload)) == RecordReader::Next::Record) {
    if (kind == kIdentity) rr.damaged("a second identity", true);
    if (kind == kTile) decoded(rr, decode_tile, payload), ++tiles;
    if (kind == kPassTile) decoded(rr, decode_pass_tile, payload), ++pass_tiles;
    if (kind == kPassStart) {
      decoded(rr, decode_pass_start, payload);
      if (++pass_starts > 1) rr.damaged("a second pass start", true);
    }
    if (tiles > 0 && pass_tiles + pass_starts > 0)
      rr.damaged("tiles of a streamed render and of a pass render together", true);
  }
  // A pass render's log is rewritten whole at each pass start, ending with the pass start: its
  // tiles without one are a log cut short by something else than an interrupted write.
  if (pass_tiles > 0 && pass_starts == 0)
    throw CheckpointError(fmt::format(
        "checkpoint '{}' is damaged: it holds {} tiles of a pass whose start is missing (cut "
        "short at byte {}?); delete it to start over",
        file_.string(), pass_tiles, rr.at()));
  end_ = rr.at();
  records_ = rr.records() - 1;
  cut_short_ = n == RecordReader::Next::Tail;
}

CheckpointReader::~CheckpointReader() {
  if (fd_ >= 0) ::close(fd_);
}

void CheckpointReader::read(const Visitor& v) {
  RecordReader rr(fd_, file_, end_, body_);
  uint32_t kind = 0;
  std::string payload;
  while (rr.next(&kind, &payload) == RecordReader::Next::Record) {
    if (kind == kTile && v.tile) v.tile(decoded(rr, decode_tile, payload));
    if (kind == kPassTile && v.pass_tile) v.pass_tile(decoded(rr, decode_pass_tile, payload));
    if (kind == kPassStart && v.pass_start) {
      auto [pass, active] = decoded(rr, decode_pass_start, payload);
      v.pass_start(pass, std::move(active));
    }
  }
  if (rr.at() != end_)
    throw CheckpointError(fmt::format("checkpoint '{}' changed while it was read", file_.string()));
}

}  // namespace anamorph
