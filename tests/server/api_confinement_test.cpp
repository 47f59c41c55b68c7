// The editor's files stay in the scene's folder by construction: it opens the folder once and
// reaches every file through that descriptor (io/confined_folder.h), so a symbolic link swapped
// in while it works can redirect neither a save nor a read. The probe's race: 632 of 718 saves in
// 8 s answered 200 while a file outside the folder was overwritten. Here a thread swaps a link to
// a file outside in and out as fast as it can while saves and edits run, and inotify counts every
// open of that file: there must be none.
#include <sys/inotify.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>

#include <fcntl.h>

#include <atomic>
#include <cstdio>
#include <map>

#include "server_fixture.h"

namespace anamorph::test {
namespace {

const std::string kTriangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

// Counts the opens of one file (IN_OPEN: any open, for reading or writing, by any process).
class OpenCounter {
 public:
  explicit OpenCounter(const fs::path& file) : fd_(inotify_init1(IN_NONBLOCK | IN_CLOEXEC)) {
    EXPECT_GE(inotify_add_watch(fd_, file.c_str(), IN_OPEN | IN_MODIFY), 0) << file;
  }
  ~OpenCounter() { close(fd_); }
  int count() {
    alignas(inotify_event) char buf[4096];
    for (;;) {
      const ssize_t n = read(fd_, buf, sizeof buf);
      if (n <= 0) return count_;
      for (ssize_t at = 0; at < n;) {
        const auto* e = reinterpret_cast<const inotify_event*>(buf + at);
        ++count_;
        at += ssize_t(sizeof(inotify_event) + e->len);
      }
    }
  }

 private:
  int fd_;
  int count_ = 0;
};

// Exchanges a symbolic link to `target` with whatever is at `at` (a plain file), back and forth,
// until stopped: renameat2(RENAME_EXCHANGE), one atomic step each, so `at` is a link half the
// time and a plain file the other half.
class Swapper {
 public:
  Swapper(fs::path at, const fs::path& target) : at_(std::move(at)) {
    link_ = at_.parent_path() / (".link-" + at_.filename().string());
    EXPECT_EQ(::symlink(target.c_str(), link_.c_str()), 0) << link_;
    thread_ = std::thread([this] { run(); });
  }
  ~Swapper() {
    stop_ = true;
    thread_.join();
  }
  long swaps() const { return swaps_; }

 private:
  void run() {
    while (!stop_)
      if (::renameat2(AT_FDCWD, link_.c_str(), AT_FDCWD, at_.c_str(), RENAME_EXCHANGE) == 0)
        ++swaps_;
  }
  fs::path at_, link_;
  std::atomic<bool> stop_{false};
  std::atomic<long> swaps_{0};
  std::thread thread_;
};

class ConfinementTest : public ServerTest {
 protected:
  void SetUp() override {
    dir.write("scene/tri.obj", kTriangle);
    outside_toml = dir.write("outside.toml", "# not the editor's\n");
    outside_obj = dir.write("outside.obj", kTriangle);
    start(dir.write("scene/scene.toml", kScene + "\n[[object]]\ntype = \"mesh\"\nfile = "
                                                 "\"tri.obj\"\n"));
  }
  fs::path folder() const { return dir.path() / "scene"; }
  fs::path outside_toml, outside_obj;
};

TEST_F(ConfinementTest, ASymlinkSwappedInDuringSavesNeverRedirectsAWrite) {
  OpenCounter opens(outside_toml);
  std::map<int, int> statuses;
  {
    dir.write("scene/copy.toml", "# a plain file\n");
    const Swapper copy(folder() / "copy.toml", outside_toml);
    const Swapper scene(folder() / "scene.toml", outside_toml);
    for (int i = 0; i < 300; ++i) {
      const Reply r = post("/api/save", json{{"name", i % 2 ? "copy.toml" : ""}});
      ++statuses[r.status];
      ASSERT_TRUE(r.status == 200 || r.status == 400) << r.status << ": " << r.body;
      if (r.status == 400) {
        EXPECT_NE(r.body.find("is a symbolic link"), std::string::npos) << r.body;
      }
    }
    std::cout << "swaps: " << copy.swaps() + scene.swaps() << "\n";
  }
  EXPECT_EQ(opens.count(), 0) << "the file outside the folder was opened";
  EXPECT_EQ(read_text(outside_toml), "# not the editor's\n");
  EXPECT_GT(statuses[200], 0) << "no save went through (" << statuses[400] << " refused)";
  std::cout << "saves: " << statuses[200] << " x 200, " << statuses[400] << " x 400\n";
}

TEST_F(ConfinementTest, ASymlinkSwappedInDuringEditsNeverReadsOutside) {
  OpenCounter opens(outside_obj);
  std::map<std::string, int> outcomes;
  dir.write("scene/swap.obj", kTriangle);
  {
    const Swapper model(folder() / "swap.obj", outside_obj);
    for (int i = 0; i < 40; ++i) {
      const Reply r = edit("object.2.file", i % 2 ? "tri.obj" : "swap.obj", version());
      ASSERT_TRUE(r.status == 200 || r.status == 400) << r.status << ": " << r.body;
      const std::string why = body_of(r).value("error", "");
      ++outcomes[r.status == 200                                  ? "200"
                 : why.find("symbolic link") != std::string::npos ? "400 (a link, on opening)"
                 : why.find("outside") != std::string::npos       ? "400 (outside, checked first)"
                                                                  : "400 " + why];
    }
  }
  EXPECT_EQ(opens.count(), 0) << "the file outside the folder was opened";
  for (const auto& [what, n] : outcomes) std::cout << "edits: " << n << " x " << what << "\n";
  EXPECT_GE(outcomes["200"], 20) << "the edits naming tri.obj must go through";
}

// A FIFO, a device, a directory or a socket named by an edit is refused at once: a FIFO used to
// block the request's thread in open(2), and then SIGTERM no longer stopped the server (whose
// stop joins that thread; TearDown stops it here).
TEST_F(ConfinementTest, EditsNamingFilesThatAreNotRegularAre400AtOnce) {
  ASSERT_EQ(mkfifo((folder() / "fifo.obj").c_str(), 0600), 0);
  ASSERT_EQ(mkfifo((folder() / "fifo.toml").c_str(), 0600), 0);
  ASSERT_EQ(mkfifo((folder() / "fifo.exr").c_str(), 0600), 0);
  fs::create_directories(folder() / "dir.obj");
  const int sock = socket(AF_UNIX, SOCK_STREAM, 0);
  sockaddr_un a{};
  a.sun_family = AF_UNIX;
  std::snprintf(a.sun_path, sizeof a.sun_path, "%s", (folder() / "sock.obj").c_str());
  ASSERT_EQ(bind(sock, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
  const json table = {{"type", "table"}, {"file", "fifo.exr"}};
  const json camera = {{"org", table}, {"dir", table}};
  const std::vector<std::tuple<std::string, json, std::string>> cases = {
      {"object.2.file", "fifo.obj", "is a FIFO, not a regular file"},
      {"include", "fifo.toml", "is a FIFO, not a regular file"},
      {"camera", camera, "is a FIFO, not a regular file"},
      {"object.2.file", "dir.obj", "is a directory"},
      {"object.2.file", "sock.obj", "is a socket, not a regular file"},
      {"object.2.file", "/dev/zero", "outside the scene's folder"}};
  for (const auto& [key, value, says] : cases) {
    const Reply r = edit(key, value, version());
    EXPECT_EQ(r.status, 400) << key << " = " << value << ": " << r.body;
    EXPECT_NE(r.body.find(says), std::string::npos) << key << " = " << value << ": " << r.body;
  }
  close(sock);
  EXPECT_EQ(state()["document"]["object"][2]["file"], "tri.obj");
}

// The name is checked before the file system sees it: a 300-character name answered 500 with
// the system's "File name too long" (the temporary beside it is longer still).
TEST_F(ConfinementTest, ALongSaveNameIs400WithAClearMessage) {
  for (const size_t length : {300, 256, 201}) {
    const std::string name = std::string(length - 5, 'n') + ".toml";
    const Reply r = post("/api/save", json{{"name", name}});
    EXPECT_EQ(r.status, 400) << length << ": " << r.body;
    EXPECT_NE(r.body.find("the name is too long (" + std::to_string(length) + " bytes"),
              std::string::npos)
        << r.body;
    std::error_code ec;
    EXPECT_FALSE(fs::exists(folder() / name, ec)) << name;
  }
  const std::string longest = std::string(195, 'n') + ".toml";
  const Reply r = post("/api/save", json{{"name", longest}});
  EXPECT_EQ(r.status, 200) << r.body;
  EXPECT_TRUE(fs::exists(folder() / longest));
  // A file named by an edit: the system's reason, as a 400.
  const Reply file = edit("object.2.file", std::string(300, 'f') + ".obj", version());
  EXPECT_EQ(file.status, 400) << file.body;
}

}  // namespace
}  // namespace anamorph::test
