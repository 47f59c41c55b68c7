// The checkpoint reader (render/checkpoint.h): any bytes as a checkpoint file are refused with
// CheckpointError or read whole, never read past a record or allocated for beyond the file's
// size. A file read whole is then continued as `render --resume` does (the writer appends after
// the last whole record, dropping a record cut short) and must read back with exactly one
// record more. Seeds (fuzz/seeds/checkpoint): checkpoints of a streamed and of a pass render,
// cut short and with flipped bits.
#include <cstdint>
#include <cstdlib>
#include <filesystem>

#include "fuzz_util.h"
#include "render/checkpoint.h"

using namespace anamorph;

namespace {

// Every record of `file`, counted by kind; throws CheckpointError.
struct Counts {
  int tiles = 0, pass_tiles = 0, pass_starts = 0;
  int all() const { return tiles + pass_tiles + pass_starts; }
};
Counts read_all(const std::filesystem::path& file, CheckpointIdentity* id, uint64_t* end) {
  CheckpointReader r(file);
  Counts c;
  r.read({[&](ResolvedTile&&) { ++c.tiles; }, [&](PassTile&&) { ++c.pass_tiles; },
          [&](int, std::vector<uint8_t>&&) { ++c.pass_starts; }});
  if (c.all() != r.records()) std::abort();  // every record the scan counted is handed over
  if (id) *id = r.identity();
  if (end) *end = r.end();
  return c;
}

}  // namespace

// The writer fsyncs what it writes: on a disk each input waited for it (a run spent 60 % of its
// time off the CPU). In memory (/dev/shm, when there) fsync returns at once.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (std::filesystem::is_directory("/dev/shm")) setenv("TMPDIR", "/dev/shm", 0);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > (1 << 20)) return 0;
  fuzz::TempFile f(data, size, ".ckpt");
  CheckpointIdentity id;
  uint64_t end = 0;
  Counts before;
  try {
    before = read_all(f.path(), &id, &end);
  } catch (const CheckpointError&) {
    return 0;
  }
  // Continued by a resumed render: one more record of the kind the log holds.
  {
    CheckpointWriter w(f.path(), id, 1e9, end);
    if (before.pass_starts > 0) {
      const TileBuffer t(TileRect{0, 0, 2, 2}, {});
      w.add_pass_tile(before.pass_starts, 0, t);
    } else {
      ResolvedTile t;
      t.planes.emplace_back().u8.assign(16, 7);
      w.add_tile(t);
    }
  }
  const Counts after = read_all(f.path(), nullptr, nullptr);
  if (after.all() != before.all() + 1) std::abort();
  return 0;
}
