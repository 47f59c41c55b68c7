// The signal matrix (app/interrupt.h): SIGINT, SIGTERM, SIGHUP and SIGQUIT end a run in every
// phase with exit code 3, a message and no temporary file left (`serve` ends on them with 0: that
// is how it stops); SIGPIPE never kills silently: sent by kill(2) it is ignored, and a write to a
// closed pipe or FIFO is an error message with exit code 1. Each phase is caught as it happens,
// not after a guessed delay: the loader child exists (loading), the output's temporary file
// exists (rendering, `rays`), the FIFO output has data (writing), the process has its worker
// threads (`formfactors`), the editor printed its address (`serve`). Then the examples of the
// probe: a second SIGTERM keeps the image so far, SIGHUP under nohup, `-o /dev/stdout`, write
// errors on stdout.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "cli_util.h"
#include "io/image_io.h"
#include "run_fixture.h"
#include "test_util.h"

namespace anamorph {
namespace {

namespace fs = std::filesystem;
using std::chrono::seconds;

struct Signal {
  int number;
  const char* name;
};
const Signal kStops[] = {
    {SIGINT, "SIGINT"}, {SIGTERM, "SIGTERM"}, {SIGHUP, "SIGHUP"}, {SIGQUIT, "SIGQUIT"}};

// A running `anamorph ARGS`: stdout and stderr into `log` (or stdout into `out_fd`), in `dir`.
struct Process {
  pid_t pid = -1;
  fs::path log;
  Process(const std::vector<std::string>& args, const fs::path& dir, int out_fd = -1,
          bool ignore_hup = false)
      : log(dir / "log") {
    fs::remove(log);  // (a predicate must not see the last run's)
    pid = fork();
    if (pid == 0) {
      const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (fd < 0 || ::chdir(dir.c_str()) != 0) _exit(126);
      ::dup2(out_fd >= 0 ? out_fd : fd, STDOUT_FILENO);
      ::dup2(fd, STDERR_FILENO);
      if (ignore_hup) signal(SIGHUP, SIG_IGN);  // as nohup does
      const std::string bin = test::binary().string();
      std::vector<char*> argv{const_cast<char*>(bin.c_str())};
      for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      execv(bin.c_str(), argv.data());
      _exit(127);
    }
  }
  // Waits until `ready()` (true) or the process ended or `limit` passed (false).
  bool wait_for(const std::function<bool()>& ready, seconds limit = seconds(60)) const {
    const auto end = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < end) {
      if (ready()) return true;
      siginfo_t info{};
      if (::waitid(P_PID, id_t(pid), &info, WEXITED | WNOHANG | WNOWAIT) == 0 && info.si_pid == pid)
        return false;  // it ended (and stays a zombie for finish())
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return false;
  }
  // The exit code; -1 when killed by a signal (or by this, after `limit`).
  int finish(seconds limit = seconds(60)) {
    const auto end = std::chrono::steady_clock::now() + limit;
    int status = 0;
    while (::waitpid(pid, &status, WNOHANG) == 0) {
      if (std::chrono::steady_clock::now() > end) {
        ::kill(pid, SIGKILL);
        ::waitpid(pid, &status, 0);
        return -1;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    pid = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  std::string output() const { return test::read_text(log); }
  ~Process() {
    if (pid > 0) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, nullptr, 0);
    }
  }
};

// The process's children (the loader child while a model loads).
std::vector<pid_t> children_of(pid_t pid) {
  std::vector<pid_t> kids;
  for (const auto& task : fs::directory_iterator("/proc/" + std::to_string(pid) + "/task")) {
    std::ifstream in(task.path() / "children");
    for (pid_t k; in >> k;) kids.push_back(k);
  }
  return kids;
}

// A field of /proc/PID/status ("Threads", "SigIgn", ...), as text.
std::string status_field(pid_t pid, const std::string& name) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(name + ":", 0) == 0) return line.substr(name.size() + 1);
  return "";
}

int threads_of(pid_t pid) {
  const std::string t = status_field(pid, "Threads");
  return t.empty() ? 0 : std::stoi(t);
}

// Whether the process ignores (SigIgn) or catches (SigCgt) signal `sig`.
bool in_mask(pid_t pid, const std::string& mask, int sig) {
  return (std::stoull(status_field(pid, mask), nullptr, 16) >> (sig - 1)) & 1;
}

bool has_temporary(const fs::path& dir) { return !test::temporaries_in(dir).empty(); }

// A FIFO in `dir` with its read end open (without blocking) for the test.
struct Fifo {
  fs::path path;
  int fd = -1;
  Fifo(const fs::path& dir, const std::string& name) : path(dir / name) {
    // (Close-on-exec: the process under test must not hold a read end itself.)
    if (::mkfifo(path.c_str(), 0600) == 0)
      fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  }
  bool has_data() const {
    pollfd p{fd, POLLIN, 0};
    return ::poll(&p, 1, 0) == 1 && (p.revents & POLLIN);
  }
  void close() {
    if (fd >= 0) ::close(fd);
    fd = -1;
  }
  ~Fifo() { close(); }
};

const char* kSphere =
    "[image]\nwidth = 32\nheight = 32\n[render]\nantialias = \"uniform\"\ntile_size = 1024\n"
    "[camera]\nlook_from = [0, 1, 4]\nlook_at = [0, 0, 0]\n[[object]]\ntype = \"sphere\"\n";

// A 180,000-triangle OBJ: the loader child takes long enough to be seen.
std::string big_mesh_scene(const test::ScratchDir& d) {
  std::ofstream obj(d.dir / "big.obj");
  const int n = 300;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) obj << "v " << double(i) / n << " 0 " << double(j) / n << "\n";
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i + 1, b = a + 1, c = a + n + 1, e = c + 1;
      obj << "f " << a << " " << b << " " << e << "\nf " << a << " " << e << " " << c << "\n";
    }
  return d.write(
      "big.toml",
      "[image]\nwidth = 8\nheight = 8\n[[object]]\ntype = \"mesh\"\nfile = \"big.obj\"\n");
}

}  // namespace

// Loading: the signal comes while the loader child reads the model.
TEST(Signals, WhileLoading) {
  const test::ScratchDir d("signals_load");
  const std::string scene = big_mesh_scene(d);
  for (const Signal& s : kStops) {
    Process p({"render", scene, "-o", "out.png"}, d.dir);
    pid_t child = 0;
    ASSERT_TRUE(p.wait_for([&] {
      const auto kids = children_of(p.pid);
      return !kids.empty() && (child = kids[0]) > 0;
    })) << s.name
        << ": no loader child seen\n"
        << p.output();
    ::kill(p.pid, s.number);
    EXPECT_EQ(p.finish(), 3) << s.name << "\n" << p.output();
    EXPECT_CONTAINS(p.output(), "interrupted: out.png not written");
    EXPECT_FALSE(fs::exists(d.dir / "out.png")) << s.name;
    EXPECT_FALSE(has_temporary(d.dir)) << s.name;
  }
  // SIGPIPE by kill(2) is ignored: the load goes on and `info` answers.
  Process p({"info", scene}, d.dir);
  ASSERT_TRUE(p.wait_for([&] { return !children_of(p.pid).empty(); })) << p.output();
  ::kill(p.pid, SIGPIPE);
  EXPECT_EQ(p.finish(), 0) << p.output();
  EXPECT_CONTAINS(p.output(), "triangles   180000 unique");
}

// Rendering: the signal comes once the output's temporary file exists (the render has begun).
TEST(Signals, WhileRendering) {
  const test::ScratchDir d("signals_render");
  const std::string scene = d.write("s.toml", kSphere);
  for (const Signal& s : kStops) {
    Process p({"render", scene, "-q", "-o", "out.png", "--spp", "1048576"}, d.dir);
    ASSERT_TRUE(p.wait_for([&] { return has_temporary(d.dir); })) << s.name << p.output();
    ::kill(p.pid, s.number);
    EXPECT_EQ(p.finish(), 3) << s.name << "\n" << p.output();
    EXPECT_CONTAINS(p.output(),
                    "interrupted: out.png not written; the image so far is in "
                    "out.partial.png");
    EXPECT_FALSE(fs::exists(d.dir / "out.png")) << s.name;
    EXPECT_TRUE(fs::exists(d.dir / "out.partial.png")) << s.name;
    EXPECT_FALSE(has_temporary(d.dir)) << s.name;
    fs::remove(d.dir / "out.partial.png");
  }
  // SIGPIPE by kill(2): ignored, the render goes on (and SIGTERM then stops it as above).
  Process p({"render", scene, "-q", "-o", "out.png", "--spp", "1048576"}, d.dir);
  ASSERT_TRUE(p.wait_for([&] { return has_temporary(d.dir); })) << p.output();
  ::kill(p.pid, SIGPIPE);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ::kill(p.pid, SIGTERM);
  EXPECT_EQ(p.finish(), 3) << p.output();
  EXPECT_TRUE(fs::exists(d.dir / "out.partial.png"));
}

// Writing: the image is written, then --stats goes to a FIFO that the test does not read, so the
// process blocks in the write; the signal comes once data is in the FIFO.
TEST(Signals, WhileWriting) {
  const test::ScratchDir d("signals_write");
  const std::string scene = d.write("s.toml", kSphere);
  const std::vector<std::string> args = {"render",
                                         scene,
                                         "-q",
                                         "-o",
                                         "out.png",
                                         "--width",
                                         "256",
                                         "--height",
                                         "256",
                                         "--spp",
                                         "1",
                                         "--set",
                                         "render.tile_size=4",
                                         "--stats",
                                         "stats.json"};
  for (const Signal& s : kStops) {
    Fifo fifo(d.dir, "stats.json");
    Process p(args, d.dir);
    ASSERT_TRUE(p.wait_for([&] { return fifo.has_data(); })) << s.name << p.output();
    ::kill(p.pid, s.number);
    EXPECT_EQ(p.finish(), 3) << s.name << "\n" << p.output();
    EXPECT_CONTAINS(p.output(), "interrupted: stats.json not written (out.png was)");
    EXPECT_TRUE(fs::exists(d.dir / "out.png"));
    EXPECT_FALSE(has_temporary(d.dir)) << s.name;
    fs::remove(fifo.path);
    fs::remove(d.dir / "out.png");
  }
  // The reader goes away: the write fails with EPIPE, an error message, exit 1.
  Fifo fifo(d.dir, "stats.json");
  Process p(args, d.dir);
  ASSERT_TRUE(p.wait_for([&] { return fifo.has_data(); })) << p.output();
  fifo.close();
  EXPECT_EQ(p.finish(), 1) << p.output();
  EXPECT_CONTAINS(p.output(), "error: cannot write 'stats.json': write failed: Broken pipe");
  EXPECT_FALSE(has_temporary(d.dir));
}

// `rays`: CSV into a file (its temporary exists: rows are being written), EXR into a FIFO (data
// in it: the table is being written).
TEST(Signals, WhileWritingRays) {
  const test::ScratchDir d("signals_rays");
  const std::string scene = d.write("s.toml", kSphere);
  for (const Signal& s : kStops) {
    Process csv({"rays", scene, "--width", "2000", "--height", "2000", "-o", "rays.csv"}, d.dir);
    ASSERT_TRUE(csv.wait_for([&] { return has_temporary(d.dir); })) << s.name << csv.output();
    ::kill(csv.pid, s.number);
    EXPECT_EQ(csv.finish(), 3) << s.name << "\n" << csv.output();
    EXPECT_CONTAINS(csv.output(), "interrupted: rays.csv not written");
    EXPECT_FALSE(fs::exists(d.dir / "rays.csv")) << s.name;
    EXPECT_FALSE(has_temporary(d.dir)) << s.name;

    Fifo fifo(d.dir, "rays.exr");
    Process exr({"rays", scene, "--width", "300", "--height", "300", "-o", "rays.exr"}, d.dir);
    ASSERT_TRUE(exr.wait_for([&] { return fifo.has_data(); })) << s.name << exr.output();
    ::kill(exr.pid, s.number);
    EXPECT_EQ(exr.finish(), 3) << s.name << "\n" << exr.output();
    EXPECT_CONTAINS(exr.output(), "interrupted: rays.exr not written");
    fs::remove(fifo.path);
  }
  // SIGPIPE for real: the FIFO's reader goes away.
  Fifo fifo(d.dir, "rays.csv");
  Process p({"rays", scene, "--width", "300", "--height", "300", "-o", "rays.csv"}, d.dir);
  ASSERT_TRUE(p.wait_for([&] { return fifo.has_data(); })) << p.output();
  fifo.close();
  EXPECT_EQ(p.finish(), 1) << p.output();
  EXPECT_CONTAINS(p.output(), "write failed: Broken pipe");
}

// `formfactors`: the signal comes once it runs threads (the acceleration structure or the
// measurement); either way exit 3 with a message, no output file.
TEST(Signals, WhileMeasuringFormFactors) {
  const test::ScratchDir d("signals_ff");
  const std::string room = (test::source_dir() / "examples/apps/formfactor_room.toml").string();
  for (const Signal& s : kStops) {
    Process p({"formfactors", room, "--inward", "room", "--samples", "1000000", "-o", "ff.csv"},
              d.dir);
    ASSERT_TRUE(p.wait_for([&] { return threads_of(p.pid) > 1; })) << s.name << p.output();
    ::kill(p.pid, s.number);
    EXPECT_EQ(p.finish(), 3) << s.name << "\n" << p.output();
    EXPECT_CONTAINS(p.output(), "interrupted");
    EXPECT_FALSE(fs::exists(d.dir / "ff.csv")) << s.name;
    EXPECT_FALSE(has_temporary(d.dir)) << s.name;
  }
  // Its table to a closed pipe: an error message, exit 1.
  int pipe_fds[2];
  ASSERT_EQ(::pipe(pipe_fds), 0);
  ::close(pipe_fds[0]);
  Process p({"formfactors", room, "--inward", "room", "--samples", "16", "--rays", "16"}, d.dir,
            pipe_fds[1]);
  ::close(pipe_fds[1]);
  EXPECT_EQ(p.finish(), 1) << p.output();
  EXPECT_CONTAINS(p.output(), "Broken pipe");
}

// `warp --frames`: the signal comes once frame 0 is written, while frame 1 is warped: exit 3,
// frame 0 complete, no frame 1 and no temporary (the frame's sink writes one until commit).
TEST(Signals, WhileWarpingASequence) {
  const test::ScratchDir d("signals_warp");
  const std::string scene = d.write("s.toml", kSphere);
  ASSERT_EQ(test::run_cli("render -q " + scene +
                          " --set camera.preset=equirectangular --width 128 --height 64 -o " +
                          (d.dir / "in_0.exr").string())
                .code,
            0);
  for (int f : {1, 2})
    fs::copy_file(d.dir / "in_0.exr", d.dir / ("in_" + std::to_string(f) + ".exr"));
  Process p({"warp", scene, "in_%d.exr", "--source", "equirect", "--frames", "0:2", "--set",
             "camera.preset=fisheye", "--width", "900", "--height", "900", "-o", "out_%d.png"},
            d.dir);
  ASSERT_TRUE(p.wait_for([&] { return fs::exists(d.dir / "out_0.png"); })) << p.output();
  ::kill(p.pid, SIGINT);
  EXPECT_EQ(p.finish(), 3) << p.output();
  EXPECT_CONTAINS(p.output(), "interrupted: out_1.png not written; frames 0..0 were written");
  EXPECT_EQ(read_image(d.dir / "out_0.png").width, 900) << "frame 0 is not a complete PNG";
  EXPECT_FALSE(fs::exists(d.dir / "out_1.png") || fs::exists(d.dir / "out_2.png"));
  EXPECT_FALSE(has_temporary(d.dir));
}

// `serve`: the stop signals end the editor (exit 0, its normal end); SIGPIPE does not.
TEST(Signals, Serve) {
  const test::ScratchDir d("signals_serve");
  const std::string scene = d.write("s.toml", kSphere);
  for (const Signal& s : kStops) {
    Process p({"serve", scene, "--port", "0"}, d.dir);
    ASSERT_TRUE(p.wait_for([&] { return p.output().find("open http") != std::string::npos; }))
        << s.name << p.output();
    if (s.number == SIGTERM) ::kill(p.pid, SIGPIPE);  // (ignored)
    ::kill(p.pid, s.number);
    EXPECT_EQ(p.finish(), 0) << s.name << "\n" << p.output();
    EXPECT_CONTAINS(p.output(), "stopping the editor");
  }
}

// ---- the probe's examples ---------------------------------------------------------------------

// A second SIGTERM while the image so far is written does not lose it.
TEST(Signals, ASecondSigtermKeepsTheImageSoFar) {
  const test::ScratchDir d("signals_twice");
  const std::string scene = d.write("s.toml", kSphere);
  for (int gap_ms : {0, 1, 5, 20}) {
    Process p({"render", scene, "-q", "-o", "out.png", "--spp", "1048576"}, d.dir);
    ASSERT_TRUE(p.wait_for([&] { return has_temporary(d.dir); })) << p.output();
    ::kill(p.pid, SIGTERM);
    std::this_thread::sleep_for(std::chrono::milliseconds(gap_ms));
    ::kill(p.pid, SIGTERM);
    EXPECT_EQ(p.finish(), 3) << gap_ms << " ms apart\n" << p.output();
    EXPECT_TRUE(fs::exists(d.dir / "out.partial.png")) << gap_ms << " ms apart\n" << p.output();
    EXPECT_FALSE(has_temporary(d.dir));
    fs::remove(d.dir / "out.partial.png");
  }
}

// Under nohup (SIGHUP ignored when anamorph starts) the render outlives its terminal.
TEST(Signals, SighupStaysIgnoredUnderNohup) {
  const test::ScratchDir d("signals_nohup");
  const std::string scene = d.write("s.toml", kSphere);
  Process p({"render", scene, "-q", "-o", "out.png", "--spp", "1048576"}, d.dir, -1, true);
  ASSERT_TRUE(p.wait_for([&] { return has_temporary(d.dir); })) << p.output();
  EXPECT_TRUE(in_mask(p.pid, "SigIgn", SIGHUP)) << "SIGHUP is not ignored";
  for (int sig : {SIGINT, SIGTERM, SIGQUIT})
    EXPECT_TRUE(in_mask(p.pid, "SigCgt", sig)) << "signal " << sig << " is not caught";
  EXPECT_TRUE(in_mask(p.pid, "SigIgn", SIGPIPE)) << "SIGPIPE is not ignored";
  ::kill(p.pid, SIGHUP);
  ::kill(p.pid, SIGTERM);
  EXPECT_EQ(p.finish(), 3) << p.output();
  // (Had SIGHUP stopped the render, SIGTERM would have been a second signal.)
  EXPECT_EQ(p.output().find("interrupted again"), std::string::npos) << p.output();
}

// `-o /dev/stdout` into a pipe: the PNG alone on stdout (the summary goes to stderr); the same
// into a closed pipe is an error message, exit 1, no temporary.
TEST(Signals, OutputToStandardOutput) {
  const test::ScratchDir d("signals_stdout");
  const std::string scene = d.write("s.toml", kSphere);
  std::string cmd = "{ ";  // (anamorph's exit code in rc, the pipe's reader reads it all)
  cmd += test::binary().string() + " render " + scene + " -o /dev/stdout 2>";
  cmd += (d.dir / "err").string() + "; echo $? >" + (d.dir / "rc").string();
  cmd += "; } | cat >" + (d.dir / "piped.png").string();
  const test::CliResult png = test::run_shell(cmd);
  EXPECT_EQ(test::read_text(d.dir / "rc"), "0\n") << test::read_text(d.dir / "err");
  EXPECT_EQ(read_image(d.dir / "piped.png").width, 32) << png.out;
  EXPECT_CONTAINS(test::read_text(d.dir / "err"), "/dev/stdout: 32x32");
  // An EXR (written with an offset table at the end) through a FIFO.
  Fifo fifo(d.dir, "pipe.exr");
  Process p({"render", scene, "-q", "-o", "pipe.exr"}, d.dir);
  ASSERT_TRUE(p.wait_for([&] { return fifo.has_data(); })) << p.output();
  std::string exr;
  int flags = ::fcntl(fifo.fd, F_GETFL);
  ::fcntl(fifo.fd, F_SETFL, flags & ~O_NONBLOCK);
  char buf[4096];
  for (ssize_t n; (n = ::read(fifo.fd, buf, sizeof buf)) != 0;)
    if (n > 0) exr.append(buf, size_t(n));
  EXPECT_EQ(p.finish(), 0) << p.output();
  std::ofstream(d.dir / "copy.exr", std::ios::binary) << exr;
  const Image back = read_image(d.dir / "copy.exr");
  EXPECT_EQ(back.width, 32);
  // A closed pipe.
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);
  ::close(fds[0]);
  Process closed({"render", scene, "-q", "-o", "/dev/stdout"}, d.dir, fds[1]);
  ::close(fds[1]);
  EXPECT_EQ(closed.finish(), 1) << closed.output();
  EXPECT_CONTAINS(closed.output(), "error: cannot write '/dev/stdout': write failed: Broken pipe");
}

// Write errors on stdout: a full disk, a closed pipe.
TEST(Signals, WriteErrorsOnStandardOutput) {
  const test::ScratchDir d("signals_full");
  const std::string scene = d.write("s.toml", kSphere);
  std::string cmd = "(";  // (only stdout to /dev/full: run_shell reads stderr)
  cmd += test::binary().string() + " info " + scene + " > /dev/full)";
  const test::CliResult full = test::run_shell(cmd);
  EXPECT_EQ(full.code, 1) << full.out;
  EXPECT_CONTAINS(full.out, "error: cannot write to standard output: No space left on device");
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);
  ::close(fds[0]);
  Process p({"info", scene}, d.dir, fds[1]);
  ::close(fds[1]);
  EXPECT_EQ(p.finish(), 1) << p.output();
  EXPECT_CONTAINS(p.output(), "error: cannot write to standard output: Broken pipe");
}

}  // namespace anamorph
