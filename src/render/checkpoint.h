// Checkpoints: an append-only log of what a render has finished, enough to continue it and end
// with the same bits as an uninterrupted render.
//
// Layout (render/checkpoint_records.h): a 16-byte signature, then records of a header (kind,
// payload size, the payload's CRC-32 and the header's own CRC-32) and a payload. The first record
// names the render (its identity: the scene as rendered, the settings and outputs, as "key =
// value" lines); the others are finished tiles (streamed renders: the tile as the output files
// take it) or, for pass renders (per-pixel adaptive sampling), a tile's sums after a pass and the
// start of a pass with its active pixels. Records are appended as work finishes and the file is
// fsync'd every `sync_every` seconds and when closed. A render killed at any moment (SIGKILL,
// power loss) leaves at most one record cut short at the end, which is dropped; anything else
// that does not match its checksums, counts or order is damage, and the file is refused whole
// before any of it is used (never resumed from part of it, never written over).
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "io/image_io.h"
#include "render/frame_output.h"
#include "render/tile_buffer.h"

namespace anamorph {

struct CheckpointError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// What a checkpoint belongs to, as ordered "key = value" entries.
using CheckpointIdentity = std::vector<std::pair<std::string, std::string>>;
// The scene's effective TOML flattened to dotted keys ("camera.fov = 90"), for an identity.
CheckpointIdentity flatten_toml(const std::string& toml_text, const std::string& prefix = "");
// "" when equal; otherwise what changed (the entry "command", the arguments that started the
// render, is kept for resuming and not compared), e.g. "render.spp was 16, is 32; camera.fov
// changed".
std::string identity_changes(const CheckpointIdentity& saved, const CheckpointIdentity& now);

// A pass render's tile after a pass: its sums, raw.
struct PassTile {
  int pass = 0;
  size_t index = 0;
  std::vector<PixelSum> sums;
  std::vector<float> aov;
};

class CheckpointWriter {
 public:
  // A new checkpoint (replacing any file there, atomically), or, with `append_at` > 0, the
  // existing one continued after its last good record (CheckpointReader::end()).
  CheckpointWriter(const std::filesystem::path& file, const CheckpointIdentity& id,
                   double sync_every_seconds, uint64_t append_at = 0);
  ~CheckpointWriter();
  // Thread-safe.
  void add_tile(const ResolvedTile& t);
  void add_pass_tile(int pass, size_t index, const TileBuffer& tile);
  void add_pass_start(int pass, const std::vector<uint8_t>& active);
  // A pass render compacting its log: a new file with the identity, then the records added
  // until commit_rewrite() (every tile's state and the pass start), written beside the old one
  // and renamed over it only then, complete and on disk. The old log stays whole until that
  // moment (an interruption or an error in between leaves it as it was).
  void begin_rewrite();
  void commit_rewrite();
  void sync();  // fsync now
  const std::filesystem::path& file() const { return file_; }

 private:
  void record(uint32_t kind, const std::string& payload);
  void open_append();
  std::filesystem::path file_;
  std::string identity_payload_;
  double every_;
  std::mutex mu_;
  int fd_ = -1;
  std::unique_ptr<AtomicFile> rewrite_;  // the new log while a rewrite is under way
  std::chrono::steady_clock::time_point last_sync_;
};

// Reads a checkpoint: validated whole when opened, then record by record (tiles are handed over
// as read, never all at once).
class CheckpointReader {
 public:
  // Reads the identity and checks every record: signature and format, each header's and
  // payload's checksum, each payload's counts against its bytes, the order of the kinds (one
  // identity first; tiles, or pass tiles and one pass start with its tiles before it). A record
  // cut short at the very end is left out. Anything else throws CheckpointError naming the byte.
  explicit CheckpointReader(const std::filesystem::path& file);
  ~CheckpointReader();
  CheckpointReader(const CheckpointReader&) = delete;
  CheckpointReader& operator=(const CheckpointReader&) = delete;
  const CheckpointIdentity& identity() const { return id_; }
  struct Visitor {
    std::function<void(ResolvedTile&&)> tile;
    std::function<void(PassTile&&)> pass_tile;
    std::function<void(int pass, std::vector<uint8_t>&& active)> pass_start;
  };
  // Every record after the identity, in order.
  void read(const Visitor& v);
  uint64_t end() const { return end_; }          // offset after the last whole record
  int records() const { return records_; }       // after the identity
  bool cut_short() const { return cut_short_; }  // a record at the end was left out

 private:
  void scan(uint64_t file_size);
  std::filesystem::path file_;
  int fd_ = -1;
  uint64_t end_ = 0, body_ = 0;  // body_: the offset after the identity
  int records_ = 0;
  bool cut_short_ = false;
  CheckpointIdentity id_;
};

}  // namespace anamorph
