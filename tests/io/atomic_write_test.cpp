// write_file_atomic: the target holds either the old or the complete new content, and no
// temporary file survives a failure. Tests run as root, which ignores permissions, so failures
// are provoked with a directory in the target's place and with a file-size limit (RLIMIT_FSIZE
// applies to root too) that makes write(2) fail halfway.
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <fstream>

#include "io/image_io.h"
#include "io/io_test_util.h"

namespace anamorph {

class AtomicWrite : public test::ScratchDir {};

TEST_F(AtomicWrite, WritesAndReplacesLeavingNoTemporaries) {
  const auto path = dir() / "data.bin";
  const std::string first = "first version", second = "second, longer version\n";
  write_file_atomic(path, first.data(), first.size());
  EXPECT_EQ(test::file_bytes(path), std::vector<unsigned char>(first.begin(), first.end()));
  write_file_atomic(path, second.data(), second.size());
  EXPECT_EQ(test::file_bytes(path), std::vector<unsigned char>(second.begin(), second.end()));
  EXPECT_EQ(test::dir_entries(dir()), std::vector<std::string>{"data.bin"});
}

TEST_F(AtomicWrite, CreatesMissingParentDirectories) {
  const auto path = dir() / "a" / "b" / "data.bin";
  write_file_atomic(path, "x", 1);
  EXPECT_EQ(test::file_bytes(path), std::vector<unsigned char>{'x'});
}

TEST_F(AtomicWrite, DirectoryInTheWayFailsCleanly) {
  const auto path = dir() / "out.png";
  std::filesystem::create_directory(path);
  const std::string msg = test::error_of([&] { write_file_atomic(path, "x", 1); });
  EXPECT_NE(msg.find(path.string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("it is a directory"), std::string::npos) << msg;
  EXPECT_EQ(test::dir_entries(dir()), std::vector<std::string>{"out.png"});
  EXPECT_TRUE(std::filesystem::is_empty(path));
}

TEST_F(AtomicWrite, FailedWriteKeepsTheOriginalFile) {
  const auto path = dir() / "render.png";
  OutputImage small;
  small.width = small.height = 2;
  small.layers.push_back({"", {"R", "G", "B", "A"}, std::vector<float>(16, 0.5f)});
  write_png(path, small);
  const auto original = test::file_bytes(path);

  // Noise compresses badly, so this PNG is far larger than the 16 KiB limit below.
  OutputImage big;
  big.width = big.height = 256;
  big.layers.push_back({"", {"R", "G", "B", "A"}, std::vector<float>(256 * 256 * 4)});
  uint32_t s = 12345;
  for (float& v : big.layers[0].data)
    v = float((s = s * 1664525u + 1013904223u) >> 8) / 16777216.0f;

  rlimit old_limit{};
  ASSERT_EQ(getrlimit(RLIMIT_FSIZE, &old_limit), 0);
  rlimit limit = old_limit;
  limit.rlim_cur = 16 * 1024;
  auto old_handler = std::signal(SIGXFSZ, SIG_IGN);  // get EFBIG instead of being killed
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &limit), 0);
  std::string msg;
  try {
    write_png(path, big);
  } catch (const ImageIoError& e) {
    msg = e.what();
  }
  setrlimit(RLIMIT_FSIZE, &old_limit);
  std::signal(SIGXFSZ, old_handler);

  EXPECT_NE(msg.find(path.string()), std::string::npos) << "message: " << msg;
  EXPECT_NE(msg.find("File too large"), std::string::npos) << "message: " << msg;
  EXPECT_EQ(test::file_bytes(path), original);
  EXPECT_EQ(test::dir_entries(dir()), std::vector<std::string>{"render.png"});
}

TEST_F(AtomicWrite, UnsupportedExtensionKeepsTheOriginalFile) {
  const auto path = dir() / "render.tif";
  test::write_bytes(path, "precious");
  OutputImage img;
  img.width = img.height = 1;
  img.layers.push_back({"", {"R", "G", "B", "A"}, {1, 1, 1, 1}});
  EXPECT_NE(test::error_of([&] { write_image(path, img); }).find("unsupported extension"),
            std::string::npos);
  EXPECT_EQ(test::file_bytes(path),
            (std::vector<unsigned char>{'p', 'r', 'e', 'c', 'i', 'o', 'u', 's'}));
  EXPECT_EQ(test::dir_entries(dir()), std::vector<std::string>{"render.tif"});
}

TEST_F(AtomicWrite, SymlinkIsFollowedAndKept) {
  const auto real = dir() / "real.png", link = dir() / "link.png";
  write_file_atomic(real, "old", 3);
  std::filesystem::create_symlink("real.png", link);
  write_file_atomic(link, "new", 3);
  EXPECT_TRUE(std::filesystem::is_symlink(link)) << "the link must not be replaced by a file";
  EXPECT_EQ(test::file_bytes(real), (std::vector<unsigned char>{'n', 'e', 'w'}));
  EXPECT_EQ(test::dir_entries(dir()), (std::vector<std::string>{"link.png", "real.png"}));
}

TEST_F(AtomicWrite, DeviceIsWrittenNotReplaced) {
  // /dev/null as the output (e.g. to time a render): written into, and still the device after.
  write_file_atomic("/dev/null", "x", 1);
  EXPECT_TRUE(std::filesystem::is_character_file("/dev/null"));
}

TEST_F(AtomicWrite, StaleTemporariesOfDeadProcessesAreRemoved) {
  // A process that is gone (its PID reaped) and one that is alive (ours: our parent).
  const pid_t dead = fork();
  if (dead == 0) _exit(0);
  int status;
  waitpid(dead, &status, 0);
  const auto path = dir() / "out.png";
  const std::string stale = ".out.png.tmp-" + std::to_string(dead) + "-00000000deadbeef";
  const std::string live = ".out.png.tmp-" + std::to_string(getppid()) + "-0000000012345678";
  const std::string other = ".other.png.tmp-" + std::to_string(dead) + "-00000000deadbeef";
  for (const std::string& name : {stale, live, other}) std::ofstream(dir() / name) << "partial";
  write_file_atomic(path, "x", 1);
  EXPECT_EQ(test::dir_entries(dir()), (std::vector<std::string>{other, live, "out.png"}));
}

TEST_F(AtomicWrite, AbandonedWriteLeavesTheTargetAndNoTemporary) {
  const auto path = dir() / "out.csv";
  write_file_atomic(path, "old", 3);
  {
    AtomicFile f(path);
    f.write("half a ta", 9);
  }  // an exception on the way would do the same
  EXPECT_EQ(test::file_bytes(path), (std::vector<unsigned char>{'o', 'l', 'd'}));
  EXPECT_EQ(test::dir_entries(dir()), std::vector<std::string>{"out.csv"});
}

}  // namespace anamorph
