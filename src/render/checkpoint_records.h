// The checkpoint file's framing (render/checkpoint.h is the interface): a signature, then records
// of a 20-byte header and a payload, each header and each payload with a CRC-32 of its own.
//
// The header's own checksum is what tells damage from a file cut short: a length that a flipped
// bit made huge fails it, where a payload checksum alone would read it as a record still being
// written and silently drop the rest of the file.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "render/checkpoint.h"

namespace anamorph::checkpoint_detail {

// Format 2 (format 1 had no header checksum and rewrote pass logs in place).
inline constexpr char kSignature[16] = {'A', 'N', 'A', 'M', 'O', 'R', 'P', 'H',
                                        '-', 'C', 'K', 'P', 'T', '-', '2', '\n'};
inline constexpr size_t kSignatureSize = sizeof kSignature;
enum Kind : uint32_t { kIdentity = 1, kTile = 2, kPassTile = 3, kPassStart = 4 };
// kind u32, payload size u64, payload CRC-32 u32, CRC-32 of the 16 bytes before it u32.
inline constexpr size_t kHeaderSize = 20;

// The record as written: header and payload.
std::string framed(uint32_t kind, const std::string& payload);

// Reads records one after the other from an open file of `file_size` bytes, from `at`.
class RecordReader {
 public:
  RecordReader(int fd, const std::filesystem::path& file, uint64_t file_size, uint64_t at);
  enum class Next {
    Record,  // *kind and *payload hold a whole record with matching checksums
    End,     // the file ends after the last record
    Tail,    // the file ends inside a record (a write cut short) or in unwritten (zero) bytes
  };
  // Throws CheckpointError naming the byte offset when a record is damaged.
  Next next(uint32_t* kind, std::string* payload);
  uint64_t at() const { return at_; }  // the offset after the last record read
  int records() const { return records_; }
  // A CheckpointError naming the file, the offset and the number of the record being read
  // (`last`: the one next() returned last).
  [[noreturn]] void damaged(const std::string& why, bool last = false) const;

 private:
  bool read_at(uint64_t offset, void* p, size_t n) const;
  bool zero_from(uint64_t offset) const;
  int fd_;
  std::filesystem::path file_;
  uint64_t size_, at_, last_ = 0;
  int records_ = 0;
};

// Payloads, decoded exactly: a count that does not match the bytes of its record, or bytes
// left over, throw CheckpointError.
CheckpointIdentity decode_identity(const std::string& payload);
ResolvedTile decode_tile(const std::string& payload);
PassTile decode_pass_tile(const std::string& payload);
std::pair<int, std::vector<uint8_t>> decode_pass_start(const std::string& payload);

std::string encode_identity(const CheckpointIdentity& id);
std::string encode_tile(const ResolvedTile& t);
std::string encode_pass_tile(int pass, size_t index, const TileBuffer& tile);
std::string encode_pass_start(int pass, const std::vector<uint8_t>& active);

}  // namespace anamorph::checkpoint_detail
