// The one reader behind every input (io/read_file.h) and the folder the editor confines its files
// to (io/confined_folder.h): what is refused and why, the size bounds, and that no symbolic link
// is followed beneath the folder, with openat2 and with the walk used without it.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <string>
#include <variant>

#include "io/confined_folder.h"
#include "io/read_file.h"
#include "test_util.h"

namespace anamorph {
namespace {

namespace fs = std::filesystem;

class Folder {
 public:
  Folder() {
    std::random_device rd;
    path_ = fs::temp_directory_path() /
            ("anamorph-read-" + std::to_string(getpid()) + "-" + std::to_string(rd()));
    fs::create_directories(path_);
    path_ = fs::canonical(path_);
  }
  ~Folder() { fs::remove_all(path_); }
  const fs::path& path() const { return path_; }
  fs::path write(const fs::path& name, const std::string& text) const {
    fs::create_directories((path_ / name).parent_path());
    std::ofstream(path_ / name, std::ios::binary) << text;
    return path_ / name;
  }

 private:
  fs::path path_;
};

std::string reason(const fs::path& file, const InputKind& kind = kSceneInput) {
  std::vector<unsigned char> bytes;
  const auto failure = read_whole_file(file, &bytes, kind);
  return failure ? failure->reason : "read " + std::to_string(bytes.size()) + " bytes";
}

TEST(ReadFile, WhatIsNotARegularFileIsRefusedByKind) {
  Folder f;
  const fs::path fifo = f.path() / "fifo", sock = f.path() / "sock";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  const int s = socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un a{};
  a.sun_family = AF_UNIX;
  std::snprintf(a.sun_path, sizeof a.sun_path, "%s", sock.c_str());
  ASSERT_EQ(bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
  // (a FIFO with no writer: open(2) without O_NONBLOCK would wait here forever)
  EXPECT_EQ(reason(fifo), "is a FIFO, not a regular file");
  EXPECT_EQ(reason("/dev/zero"), "is a character device, not a regular file");
  EXPECT_EQ(reason("/dev/urandom"), "is a character device, not a regular file");
  EXPECT_EQ(reason(f.path()), "is a directory");
  EXPECT_EQ(reason(sock), "is a socket, not a regular file");
  EXPECT_EQ(reason(f.path() / "missing"), "No such file or directory");
  EXPECT_EQ(reason(f.write("ok.toml", "[image]\n")), "read 8 bytes");
  // A symbolic link is followed, to what it names.
  fs::create_symlink("/dev/zero", f.path() / "zero.png");
  EXPECT_EQ(reason(f.path() / "zero.png"), "is a character device, not a regular file");
  close(s);
}

TEST(ReadFile, SizeIsBoundedByTheKind) {
  Folder f;
  const InputKind small{"a test file", 1000};
  EXPECT_EQ(reason(f.write("a", std::string(1000, 'x')), small), "read 1000 bytes");
  EXPECT_EQ(reason(f.write("b", std::string(1001, 'x')), small),
            "is 1001 bytes, more than the 1000 bytes anamorph reads as a test file");
  // A sparse file larger than any image: refused from its size, nothing read.
  const fs::path big = f.path() / "big.exr";
  { std::ofstream(big).put('x'); }
  fs::resize_file(big, (uint64_t(5) << 30));
  EXPECT_EQ(reason(big, kImageInput),
            "is 5.0 GiB, more than the 4.0 GiB anamorph reads as an image file");
  // A file whose size the system does not know (0 for /proc) is read up to the bound.
  EXPECT_EQ(reason("/proc/self/maps", small),
            "holds more than the 1000 bytes anamorph reads as a test file");
  EXPECT_NE(reason("/proc/self/maps", kTextInput).find("read "), std::string::npos);
}

TEST(ReadFile, DescribeNamesTheStepAndTheFile) {
  std::vector<unsigned char> bytes;
  const auto failure = read_whole_file("/dev/zero", &bytes, kSceneInput);
  ASSERT_TRUE(failure);
  EXPECT_EQ(describe(*failure, "/dev/zero"),
            "cannot open /dev/zero: is a character device, not a regular file");
}

// The folder: plain files beneath it open; a link anywhere on the way, "..", or a path leaving
// it does not. Both ways of opening (openat2, and the walk without it) answer alike.
class Beneath : public ::testing::TestWithParam<bool> {
 protected:
  int open(const ConfinedFolder& folder, const fs::path& rel) {
    const int fd = GetParam() ? folder.open_beneath(rel, O_RDONLY)
                              : open_beneath_by_walk(folder.fd(), rel, O_RDONLY | O_CLOEXEC);
    if (fd >= 0) close(fd);
    return fd >= 0 ? 0 : fd;
  }
};

TEST_P(Beneath, OnlyPlainPathsBeneathTheFolderOpen) {
  Folder f;
  f.write("scene/a.toml", "a");
  f.write("scene/sub/b.obj", "b");
  f.write("outside.toml", "o");
  fs::create_symlink(f.path() / "outside.toml", f.path() / "scene" / "link.toml");
  fs::create_symlink("a.toml", f.path() / "scene" / "relative_link.toml");
  fs::create_symlink(f.path(), f.path() / "scene" / "up");
  fs::create_symlink("sub", f.path() / "scene" / "sublink");
  const ConfinedFolder folder(f.path() / "scene");
  EXPECT_EQ(open(folder, "a.toml"), 0);
  EXPECT_EQ(open(folder, "sub/b.obj"), 0);
  EXPECT_EQ(open(folder, "link.toml"), -ELOOP);
  EXPECT_EQ(open(folder, "relative_link.toml"), -ELOOP);  // (even one that stays inside)
  EXPECT_EQ(open(folder, "up/outside.toml"), -ELOOP);
  EXPECT_EQ(open(folder, "sublink/b.obj"), -ELOOP);
  EXPECT_EQ(open(folder, "../outside.toml"), -EXDEV);
  EXPECT_EQ(open(folder, "missing"), -ENOENT);
}

INSTANTIATE_TEST_SUITE_P(OpenAt2AndWalk, Beneath, ::testing::Bool());

TEST(ConfinedFolder, RelativeIsDecidedAsText) {
  Folder f;
  const ConfinedFolder folder(f.path());
  EXPECT_EQ(folder.relative(f.path() / "a" / "b.obj"), fs::path("a/b.obj"));
  EXPECT_EQ(folder.relative(f.path() / "a" / ".." / "b.obj"), fs::path("b.obj"));
  EXPECT_FALSE(folder.relative(f.path() / ".." / "b.obj"));
  EXPECT_FALSE(folder.relative("/etc/passwd"));
  EXPECT_FALSE(folder.relative(f.path()));
}

TEST(ConfinedFolder, WriteAtomicReplacesPlainFilesAndNeverALinksTarget) {
  Folder f;
  const ConfinedFolder folder(f.path());
  EXPECT_FALSE(folder.write_atomic("new.toml", "one"));
  EXPECT_EQ(test::read_text(f.path() / "new.toml"), "one");
  EXPECT_FALSE(folder.write_atomic("new.toml", "two"));
  EXPECT_EQ(test::read_text(f.path() / "new.toml"), "two");
  const fs::path outside = f.write("out/target.toml", "outside");
  fs::create_symlink(outside, f.path() / "link.toml");
  EXPECT_EQ(folder.write_atomic("link.toml", "x"), "it is a symbolic link");
  EXPECT_EQ(test::read_text(outside), "outside");
  fs::create_directories(f.path() / "dir.toml");
  EXPECT_EQ(folder.write_atomic("dir.toml", "x"), "it is not a regular file");
  EXPECT_EQ(folder.write_atomic("out/target.toml", "x"), "not a file name in the folder");
  EXPECT_EQ(folder.write_atomic("..", "x"), "not a file name in the folder");
  EXPECT_EQ(test::read_text(outside), "outside");
  // No temporary is left beside them.
  for (const auto& e : fs::directory_iterator(f.path()))
    EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
}

// With a confinement installed (the editor's loads), reads follow its rule.
TEST(ReadConfinement, FilesBeneathTheFolderOnlyWithoutLinksAndTrustedOnesAsTheyAre) {
  Folder f;
  const fs::path inside = f.write("scene/tex.png", "png");
  const fs::path outside = f.write("shared/model.obj", "obj");
  fs::create_symlink(outside, f.path() / "scene" / "link.obj");
  const ConfinedFolder folder(f.path() / "scene");
  std::set<std::string> trusted;
  {
    const ScopedReadConfinement record({nullptr, nullptr, &trusted});
    EXPECT_EQ(reason(outside), "read 3 bytes");
  }
  EXPECT_EQ(trusted, std::set<std::string>{outside.string()});
  const ScopedReadConfinement confined({&folder, &trusted, nullptr});
  EXPECT_EQ(reason(inside), "read 3 bytes");
  EXPECT_EQ(reason(outside), "read 3 bytes");  // (read when the server started)
  EXPECT_EQ(reason(f.path() / "scene" / "link.obj"),
            "is reached through a symbolic link: the editor reads only files in the scene's "
            "folder, and follows no links there");
  EXPECT_EQ(reason(f.write("shared/other.obj", "x")), "is outside the scene's folder (" +
                                                          folder.path().string() +
                                                          "): the editor reads files only there");
  EXPECT_EQ(reason("/dev/zero"), "is outside the scene's folder (" + folder.path().string() +
                                     "): the editor reads files only there");
  EXPECT_EQ(confining_folder(inside), &folder);
  EXPECT_EQ(confining_folder(outside), nullptr);
}

}  // namespace
}  // namespace anamorph
