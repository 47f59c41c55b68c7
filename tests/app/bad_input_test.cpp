// Inputs that once crashed, hung or exhausted memory (tests/data/bad/README.md), run through the
// command line as a user would: each must end within its time limit with exit code 2 (or 0 where
// the input is valid), a message that says what is wrong, and no output file.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>

#include "cli_util.h"
#include "test_util.h"

namespace anamorph {
namespace {

namespace fs = std::filesystem;

using Result = test::CliResult;
Result run(const std::string& args, int limit_seconds = 60) {
  return test::run_cli(args, limit_seconds);
}

fs::path bad(const std::string& name) { return test::data_dir() / "bad" / name; }

struct Scratch {
  fs::path dir = fs::temp_directory_path() / ("anamorph_bad_" + std::to_string(getpid()));
  Scratch() { fs::create_directories(dir); }
  ~Scratch() { fs::remove_all(dir); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(dir / name) << text;
    return (dir / name).string();
  }
};

// A small scene that loads `model` as a mesh object.
std::string mesh_scene(const Scratch& s, const fs::path& model) {
  return s.write("mesh.toml",
                 "[image]\nwidth = 8\nheight = 8\n[[object]]\ntype = \"mesh\"\nfile = \"" +
                     model.string() + "\"\n");
}

// Starts the binary with `args`, sends `sig` after `delay`, and waits at most `limit` for it to
// end (then SIGKILL: a hang fails the test instead of stalling the suite). Returns the exit code,
// -1 when it did not exit by itself; stderr goes to `log`.
int signal_after(const std::vector<std::string>& args, std::chrono::milliseconds delay, int sig,
                 const fs::path& log, std::chrono::seconds limit = std::chrono::seconds(60)) {
  const pid_t pid = test::spawn(args, log, true);
  std::this_thread::sleep_for(delay);
  kill(pid, sig);
  const auto end = std::chrono::steady_clock::now() + limit;
  int status = 0;
  while (waitpid(pid, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > end) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      return -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

TEST(BadInput, SixtyFiveCoincidentCoinsRenderAndGiveRays) {
  Scratch s;
  const fs::path out = s.dir / "coins.png";
  const Result r = run("render " + bad("coins_65_coincident.toml").string() + " -o " +
                       out.string() + " --spp 1");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(fs::exists(out));
  const Result rays = run("rays " + bad("coins_65_coincident.toml").string() + " --width 8 " +
                          "--height 8 -o " + (s.dir / "rays.csv").string());
  EXPECT_EQ(rays.code, 0) << rays.out;
}

TEST(BadInput, PlyFaceWithoutCornersCrashesOnlyTheLoaderProcess) {
  Scratch s;
  const Result r = run("info " + mesh_scene(s, bad("ply_face_without_corners.ply")));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_CONTAINS(r.out, "ply_face_without_corners.ply: assimp crashed on it (signal 6 SIGABRT)");
  EXPECT_CONTAINS(r.out, "mesh.toml:6:8: object[0].file");
}

// Model files whose sizes or structure are checked before anything is allocated for them.
struct RejectedModel {
  const char* file;
  const char* message;
};

TEST(BadInput, ModelsAreRejectedBeforeAllocatingOrHanging) {
  const RejectedModel cases[] = {
      // assimp 5.2.5 loops forever on it: rejected at once.
      {"ply_header_without_end.ply", "the PLY header has no end_header line"},
      {"ply_two_billion_vertices.ply",
       "declares 2000000000 vertex elements, more than the file's 169 bytes"},
      {"gltf_node_dag.gltf", "node 1 is a child of node 0 and of node 0"},
      {"gltf_accessor_count_without_data.gltf",
       "accessor 0: 400000000 elements without a bufferView"},
  };
  for (const RejectedModel& c : cases) {
    Scratch s;
    const Result r = run("info " + mesh_scene(s, bad(c.file)), 20);
    EXPECT_EQ(r.code, 2) << c.file << ": " << r.out;
    EXPECT_CONTAINS(r.out, c.message);
  }
}

TEST(BadInput, IncludeFanOutStopsWithAnError) {
  const Result r = run("info " + bad("fanout_00.toml").string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_CONTAINS(r.out, "more than 1000 files included in all");
}

TEST(BadInput, HugeTextureIsRefusedFromItsHeader) {
  Scratch s;
  const std::string scene =
      s.write("tex.toml",
              "[image]\nwidth = 8\nheight = 8\n[[material]]\nname = \"t\"\ncolor = { type = "
              "\"image\", file = \"" +
                  bad("png_16000_square_header.png").string() +
                  "\" }\n[[object]]\ntype = \"sphere\"\nmaterial = \"t\"\n");
  const Result r = run("info " + scene);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_CONTAINS(r.out, "16000 x 16000 pixels is more than the 134 million pixels");
}

TEST(BadInput, DirectoryAsSceneOrIncludeIsAnError) {
  Scratch s;
  fs::create_directories(s.dir / "sub");
  const Result r = run("render " + (s.dir / "sub").string() + " -o " + (s.dir / "x.png").string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_CONTAINS(r.out, "is a directory");
  EXPECT_FALSE(fs::exists(s.dir / "x.png"));
  const Result inc = run("info " + s.write("inc.toml", "include = \"sub\"\n"));
  EXPECT_EQ(inc.code, 2) << inc.out;
  EXPECT_CONTAINS(inc.out, "is a directory");
}

TEST(BadInput, UnreadableSceneSaysSoNotSyntaxError) {
  if (geteuid() == 0) {
    // root reads any file whatever its mode; /proc/self/mem opens but fails to read (EIO).
    const Result r = run("info /proc/self/mem");
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_CONTAINS(r.out, "cannot read /proc/self/mem: Input/output error");
    EXPECT_EQ(r.out.find("syntax"), std::string::npos) << r.out;
    return;
  }
  Scratch s;
  const std::string scene = s.write("locked.toml", "[image]\n");
  fs::permissions(scene, fs::perms::none);
  const Result r = run("info " + scene);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_CONTAINS(r.out, "Permission denied");
  EXPECT_EQ(r.out.find("syntax"), std::string::npos) << r.out;
}

// A scene path that is a FIFO nobody writes blocked in open() forever (only a signal ended it):
// now it is opened without waiting and refused at once (io/read_file.h). InputKinds.* hold every
// other role and kind.
TEST(BadInput, FifoAsSceneIsRefusedAtOnce) {
  Scratch s;
  const fs::path fifo = s.dir / "scene.toml";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  const Result r = run("info " + fifo.string(), 20);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_CONTAINS(r.out, "scene.toml: is a FIFO, not a regular file");
}

// Rendering: one tile of a million samples per pixel (the probe's --spp 1048576 took 14 s to
// stop, checked between tiles only); it must stop within a packet, leave the output unwritten
// and say where the image so far is (exit 3: interrupted).
TEST(BadInput, SigtermStopsARenderInsideATile) {
  Scratch s;
  const std::string scene = s.write(
      "s.toml",
      "[image]\nwidth = 32\nheight = 32\n[render]\nantialias = \"uniform\"\ntile_size = 1024\n"
      "[camera]\nlook_from = [0, 1, 4]\nlook_at = [0, 0, 0]\n[[object]]\ntype = \"sphere\"\n");
  const fs::path out = s.dir / "out.png";
  const int code = signal_after({"render", scene, "-q", "-o", out.string(), "--spp", "1048576"},
                                std::chrono::milliseconds(1000), SIGTERM, s.dir / "log");
  const std::string log = test::read_text(s.dir / "log");
  EXPECT_EQ(code, 3) << log;
  EXPECT_NE(log.find("interrupted: " + out.string() + " not written"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_TRUE(fs::exists(s.dir / "out.partial.png"));
}

TEST(BadInput, TruncatedObjWarns) {
  Scratch s;
  std::ifstream in(test::source_dir() / "examples" / "models" / "torus_knot.obj");
  std::string obj((std::istreambuf_iterator<char>(in)), {});
  // Cut inside the last face line: the model loads, and the warning says why it may look odd.
  obj.resize(obj.rfind('\n') - 3);
  const std::string model = s.write("cut.obj", obj);
  const Result r = run("info " + mesh_scene(s, model));
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_CONTAINS(r.out, "cut.obj: ends in the middle of a line (cut short?)");
}

TEST(BadInput, CameraWithoutRaysWarns) {
  Scratch s;
  const Result r = run("info " + s.write("noray.toml",
                                         "[camera]\norg = { type = \"point\" }\n"
                                         "dir = { type = \"expression\", x = \"1/0\", y = \"0\", "
                                         "z = \"-1\" }\n"));
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_CONTAINS(r.out, "camera: gives no ray at any of 289 image positions tried");
}

TEST(BadInput, CorruptImageInCompareIsBadInput) {
  const std::string corrupt = (test::data_dir() / "io" / "corrupt.png").string();
  const Result r = run("compare " + corrupt + " " + corrupt);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_CONTAINS(r.out, "cannot read image");
}

TEST(BadInput, BadFramePatternIsBadInput) {
  Scratch s;
  const std::string scene = s.write("s.toml", "[image]\nwidth = 4\nheight = 4\n");
  const Result r = run("render " + scene + " --frames 0:1 -o " + (s.dir / "x_%d_%s.png").string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_CONTAINS(r.out, "needs one frame-number pattern and no other %");
  EXPECT_FALSE(fs::exists(s.dir / "x_0_.png"));
}

// An interrupted frame sequence says which frames it wrote (was: "nothing written" after
// thousands of frames). Frame 0 takes one sample, frame 1 a million: the signal comes once frame
// 0 is on disk.
TEST(BadInput, InterruptedFramesSayWhichWereWritten) {
  Scratch s;
  const std::string scene = s.write(
      "s.toml",
      "[image]\nwidth = 32\nheight = 32\n[render]\nantialias = \"uniform\"\ntile_size = 1024\n"
      "[camera]\nlook_from = [0, 1, 4]\nlook_at = [0, 0, 0]\n[[object]]\ntype = \"sphere\"\n"
      "[[animate]]\nkey = \"render.spp\"\nkeys = [[0, 1], [1, 1048576]]\ninterpolation = "
      "\"step\"\n");
  const fs::path pattern = s.dir / "f_%d.png", log = s.dir / "log";
  const pid_t pid = fork();
  if (pid == 0) {
    const std::string bin = test::binary().string();
    if (!freopen(log.c_str(), "w", stderr)) _exit(126);
    execl(bin.c_str(), bin.c_str(), "render", scene.c_str(), "-q", "--frames", "0:1", "-o",
          pattern.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  for (int i = 0; i < 3000 && !fs::exists(s.dir / "f_0.png"); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  // (Frame 1's load takes milliseconds; its render, with a million samples, far longer.)
  std::this_thread::sleep_for(std::chrono::milliseconds(400));
  kill(pid, SIGTERM);
  int status = 0;
  waitpid(pid, &status, 0);
  const std::string out = test::read_text(log);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 3) << out;
  EXPECT_TRUE(fs::exists(s.dir / "f_0.png"));
  EXPECT_FALSE(fs::exists(s.dir / "f_1.png"));
  EXPECT_NE(out.find("f_1.png not written"), std::string::npos) << out;
  EXPECT_NE(out.find("frames 0..0 were written; frame 1 and later were not"), std::string::npos)
      << out;
}

}  // namespace anamorph
