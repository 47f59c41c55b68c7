// Damaged checkpoints: a log cut short by an interrupted write resumes from its last whole
// record; anything else (a log cut elsewhere, any flipped bit, an older format) is refused whole
// with the byte it starts at, before any of it is used, and the file is left as it was.
#include <gtest/gtest.h>
#include <unistd.h>

#include <fmt/format.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "app/cli_util.h"
#include "render/checkpoint.h"
#include "test_util.h"

namespace anamorph {
namespace {

namespace fs = std::filesystem;

struct Scratch {
  fs::path dir = fs::temp_directory_path() / ("anamorph_ckdamage_" + std::to_string(getpid()));
  Scratch() { fs::create_directories(dir); }
  ~Scratch() { fs::remove_all(dir); }
};

std::string bytes_of(const fs::path& p) { return test::read_text(p); }
void write_bytes(const fs::path& p, const std::string& b) {
  std::ofstream(p, std::ios::binary | std::ios::trunc) << b;
}

const CheckpointIdentity kId = {{"anamorph", "test"}, {"camera.fov", "90"}, {"command", "x"}};

ResolvedTile tile(size_t index) {
  ResolvedTile t;
  t.index = index;
  t.planes.emplace_back().u8.assign(4, static_cast<unsigned char>(index));
  return t;
}

// A streamed render's log of `n` tiles; the offsets where each record ends.
std::vector<uint64_t> streamed_log(const fs::path& f, int n) {
  std::vector<uint64_t> ends;
  CheckpointWriter w(f, kId, 1e9);
  ends.push_back(fs::file_size(f));
  for (int i = 0; i < n; ++i) {
    w.add_tile(tile(size_t(i)));
    ends.push_back(fs::file_size(f));
  }
  return ends;
}

// A pass render's log: 3 tile states and the start of pass 1 (written as one rewrite), then 2
// tiles of that pass appended. Returns where the rewrite ends.
uint64_t pass_log(const fs::path& f) {
  CheckpointWriter w(f, kId, 1e9);
  const TileBuffer t(TileRect{0, 0, 1, 1}, {});
  w.begin_rewrite();
  for (size_t i = 0; i < 3; ++i) w.add_pass_tile(0, i, t);
  w.add_pass_start(1, std::vector<uint8_t>(4, 1));
  w.commit_rewrite();
  const uint64_t rewritten = fs::file_size(f);
  w.add_pass_tile(1, 0, t);
  w.add_pass_tile(1, 1, t);
  return rewritten;
}

int records_read(const fs::path& f) {
  CheckpointReader r(f);
  int n = 0;
  r.read({[&](ResolvedTile&&) { ++n; }, [&](PassTile&&) { ++n; },
          [&](int, std::vector<uint8_t>&&) { ++n; }});
  EXPECT_EQ(n, r.records());
  return n;
}

// Cut at every length: what an interrupted append leaves resumes from the last whole record
// before the cut (and says that it dropped one); a cut into the identity is refused.
TEST(CheckpointFile, EveryCutOfAStreamedLogResumesFromItsLastWholeRecord) {
  Scratch s;
  const fs::path whole = s.dir / "whole.ckpt", cut = s.dir / "cut.ckpt";
  const std::vector<uint64_t> ends = streamed_log(whole, 5);
  const std::string b = bytes_of(whole);
  ASSERT_EQ(b.size(), ends.back());
  for (uint64_t len = 0; len <= b.size(); ++len) {
    write_bytes(cut, b.substr(0, len));
    SCOPED_TRACE(fmt::format("cut to {} of {} bytes", len, b.size()));
    if (len < ends[0]) {
      EXPECT_THROW(CheckpointReader{cut}, CheckpointError);
      continue;
    }
    int whole_records = 0;
    while (whole_records + 1 < int(ends.size()) && ends[size_t(whole_records) + 1] <= len)
      ++whole_records;
    EXPECT_EQ(records_read(cut), whole_records);
    const CheckpointReader r(cut);
    EXPECT_EQ(r.end(), ends[size_t(whole_records)]);
    EXPECT_EQ(r.cut_short(), len != r.end());
  }
}

// A pass log is rewritten whole and renamed in place once its pass start is written: a cut
// before that start cannot come from an interrupted write, and is refused.
TEST(CheckpointFile, APassLogCutBeforeItsPassStartIsRefused) {
  Scratch s;
  const fs::path whole = s.dir / "whole.ckpt", cut = s.dir / "cut.ckpt";
  const uint64_t rewritten = pass_log(whole);
  const std::string b = bytes_of(whole);
  EXPECT_EQ(records_read(whole), 6);
  int refused = 0;
  for (uint64_t len = rewritten - 1; len > 16; --len) {
    write_bytes(cut, b.substr(0, len));
    try {
      EXPECT_EQ(records_read(cut), 0) << "cut to " << len << " bytes: only the identity remains";
    } catch (const CheckpointError& e) {
      ++refused;
      const std::string m = e.what();
      EXPECT_TRUE(m.find("whose start is missing") != m.npos || m.find("identity") != m.npos)
          << "cut to " << len << ": " << m;
    }
  }
  EXPECT_GT(refused, 0);
  for (uint64_t len = rewritten; len <= b.size(); ++len) {
    write_bytes(cut, b.substr(0, len));
    EXPECT_GE(records_read(cut), 4) << "cut to " << len << " bytes, after the pass start";
  }
}

// One flipped bit anywhere (signature, a header's kind, size or checksums, a payload's counts or
// data) is damage: refused, naming the byte, never read as a shorter log. (Every byte, each with
// one of its bits in turn: all eight of every byte took 17 s under the sanitizers.)
TEST(CheckpointFile, EveryFlippedBitIsRefused) {
  Scratch s;
  const fs::path whole = s.dir / "whole.ckpt", bad = s.dir / "bad.ckpt";
  pass_log(whole);
  const std::string b = bytes_of(whole);
  size_t accepted = 0;
  std::string first_accepted;
  for (size_t i = 0; i < b.size(); ++i) {
    const int bit = int(i % 8);
    std::string f = b;
    f[i] = char(f[i] ^ (1 << bit));
    write_bytes(bad, f);
    try {
      CheckpointReader r(bad);
      if (accepted++ == 0) first_accepted = fmt::format("byte {} bit {}", i, bit);
    } catch (const CheckpointError& e) {
      const std::string m = e.what();
      if (i >= 16 && m.find("is damaged at byte") == m.npos)
        ADD_FAILURE() << "byte " << i << " bit " << bit << ": " << m;
    }
  }
  EXPECT_EQ(accepted, 0u) << "first accepted: " << first_accepted << " of " << b.size() << " bytes";
}

// A rewrite goes to a file of its own: until committed the old log stays byte for byte.
TEST(CheckpointFile, ARewriteReplacesTheLogOnlyWhenCommitted) {
  Scratch s;
  const fs::path f = s.dir / "log.ckpt";
  pass_log(f);
  const std::string before = bytes_of(f);
  {
    CheckpointWriter w(f, kId, 1e9, CheckpointReader(f).end());
    const TileBuffer t(TileRect{0, 0, 1, 1}, {});
    w.begin_rewrite();
    w.add_pass_tile(1, 0, t);
    EXPECT_EQ(bytes_of(f), before) << "the rewrite wrote into the log it replaces";
  }  // (destroyed without commit_rewrite: an interruption)
  EXPECT_EQ(bytes_of(f), before);
  size_t others = 0;
  for (const auto& e : fs::directory_iterator(s.dir)) others += e.path() != f;
  EXPECT_EQ(others, 0u) << "the unfinished rewrite's file was left behind";
}

TEST(CheckpointFile, TheFirstFormatIsRefusedWithAClearMessage) {
  Scratch s;
  const fs::path f = s.dir / "old.ckpt";
  write_bytes(f, std::string("ANAMORPH-CKPT-1\n") + std::string(40, '\0'));
  try {
    CheckpointReader r(f);
    ADD_FAILURE() << "a format-1 checkpoint was read";
  } catch (const CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("checkpoint format 1"), std::string::npos) << e.what();
  }
}

// The probe's case end to end: a pass render's checkpoint cut short (it made `--resume` fault in
// CheckpointWriter::add_pass_tile after replacing the checkpoint with its first kilobyte), and a
// flipped byte in a record's size (it resumed from nothing). Refused with exit 2; the file stays.
TEST(CheckpointFile, ADamagedCheckpointIsRefusedAndKeptByResume) {
  Scratch s;
  const fs::path scene = s.dir / "s.toml", ck = s.dir / "r.ckpt", out = s.dir / "out.png";
  std::ofstream(scene) << "[image]\nwidth = 32\nheight = 32\n[render]\nintegrator = \"path\"\n"
                          "antialias = \"pixel\"\nmax_spp = 1000000\nnoise_threshold = 1e-5\n"
                          "time_limit = 0.3\ntile_size = 8\n[environment]\ncolor = [1, 1, 1]\n"
                          "[[object]]\ntype = \"sphere\"\ncenter = [0, 0, -3]\n";
  const test::CliResult first =
      test::run_cli(fmt::format("render {} -q --threads 1 -o {} --checkpoint {}", scene.string(),
                                out.string(), ck.string()),
                    120);
  ASSERT_EQ(first.code, 0) << first.out;
  ASSERT_TRUE(fs::exists(ck)) << "the time limit keeps the checkpoint";
  const std::string good = bytes_of(ck);
  const auto resume = [&](const std::string& bytes, const char* what) {
    write_bytes(ck, bytes);
    const test::CliResult r = test::run_cli("render --resume " + ck.string() + " -q", 120);
    EXPECT_EQ(r.code, 2) << what << ": " << r.out;
    EXPECT_NE(r.out.find("is damaged"), std::string::npos) << what << ": " << r.out;
    EXPECT_TRUE(bytes_of(ck) == bytes) << what << ": the checkpoint was changed";
  };
  resume(good.substr(0, good.size() * 2 / 5), "cut to 40 %");
  resume(good.substr(0, good.size() / 10), "cut to 10 %");
  std::string flipped = good;
  flipped[16 + 4] = char(flipped[16 + 4] ^ 0x40);  // the identity record's size
  resume(flipped, "identity size flipped");
  // The second record's size (after the signature, the identity's 20-byte header and payload).
  uint64_t identity_size = 0;
  std::memcpy(&identity_size, good.data() + 16 + 4, 8);
  flipped = good;
  flipped[16 + 20 + identity_size + 4 + 1] ^= 0x01;
  resume(flipped, "second record's size flipped");
}

}  // namespace
}  // namespace anamorph
