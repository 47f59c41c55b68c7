// Checkpoints: an append-only log of what a render has finished, enough to continue it and end
// with the same bits as an uninterrupted render.
//
// Layout: a 16-byte signature, then records: kind (u32), CRC-32 of the payload (u32), payload
// size (u64), payload. The first record names the render (its identity: the scene as rendered,
// the settings and outputs, as "key = value" lines); the others are finished tiles (streamed
// renders: the tile as the output files take it) or, for pass renders (per-pixel adaptive
// sampling), a tile's sums after a pass and the start of a pass with its active pixels. Records
// are appended as work finishes and the file is fsync'd every `sync_every` seconds and when
// closed; a record counts only when complete with a matching checksum, so a render killed at any
// moment (SIGKILL, power loss) leaves a checkpoint that resumes from its last good record.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

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
  // A new checkpoint (replacing any file there), or, with `append_at` > 0, the existing one
  // continued after its last good record (CheckpointReader::end()).
  CheckpointWriter(const std::filesystem::path& file, const CheckpointIdentity& id,
                   double sync_every_seconds, uint64_t append_at = 0);
  ~CheckpointWriter();
  // Thread-safe.
  void add_tile(const ResolvedTile& t);
  void add_pass_tile(int pass, size_t index, const TileBuffer& tile);
  void add_pass_start(int pass, const std::vector<uint8_t>& active);
  // Starts the file again with only the identity (a pass render compacting its log: then it
  // writes every tile's state anew). Atomic: a new file renamed over the old.
  void restart();
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
  std::chrono::steady_clock::time_point last_sync_;
};

// Reads a checkpoint record by record (tiles are handed over as read, never all at once).
class CheckpointReader {
 public:
  explicit CheckpointReader(const std::filesystem::path& file);  // reads the identity
  ~CheckpointReader();
  const CheckpointIdentity& identity() const { return id_; }
  struct Visitor {
    std::function<void(ResolvedTile&&)> tile;
    std::function<void(PassTile&&)> pass_tile;
    std::function<void(int pass, std::vector<uint8_t>&& active)> pass_start;
  };
  // Every good record after the identity; stops at the first damaged or incomplete one.
  void read(const Visitor& v);
  uint64_t end() const { return end_; }  // offset after the last good record

 private:
  bool next(uint32_t* kind, std::string* payload);
  std::filesystem::path file_;
  int fd_ = -1;
  uint64_t end_ = 0;
  CheckpointIdentity id_;
};

}  // namespace anamorph
