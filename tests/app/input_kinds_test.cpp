// Every input role of the command line fed every kind of file that is not a regular file: a
// character device that never ends (/dev/zero) or never repeats (/dev/urandom), a FIFO with no
// writer, a directory and a socket. Each must end at once with exit 2 and a message that says
// what the file is, in bounded memory: the run is limited in address space (as the probe's was,
// except under AddressSanitizer, whose shadow needs terabytes of it) and its peak resident size is
// read back. Before io/read_file.h, /dev/zero as a table, texture or include grew to the limit and
// a FIFO blocked in open(2) forever.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "cli_util.h"
#include "test_util.h"

namespace anamorph {
namespace {

namespace fs = std::filesystem;

struct Outcome {
  int code = -1;  // -1: killed (the time limit)
  std::string out;
  long peak_kb = 0;  // peak resident size
};

// `anamorph args...` with its output in `log`, killed after `limit`; memory limited to 4 GiB of
// address space (not under ASan).
Outcome run_bounded(const std::vector<std::string>& args, const fs::path& log,
                    std::chrono::seconds limit = std::chrono::seconds(30)) {
  const pid_t pid = fork();
  if (pid == 0) {
#ifndef ANAMORPH_ASAN
    const rlimit as{rlim_t(4) << 30, rlim_t(4) << 30};
    setrlimit(RLIMIT_AS, &as);
#endif
    const std::string bin = test::binary().string();
    std::vector<char*> argv{const_cast<char*>(bin.c_str())};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    if (!freopen(log.c_str(), "w", stderr) || dup2(fileno(stderr), 1) < 0) _exit(126);
    execv(bin.c_str(), argv.data());
    _exit(127);
  }
  Outcome r;
  int status = 0;
  rusage usage{};
  const auto end = std::chrono::steady_clock::now() + limit;
  while (wait4(pid, &status, WNOHANG, &usage) == 0) {
    if (std::chrono::steady_clock::now() > end) {
      kill(pid, SIGKILL);
      wait4(pid, &status, 0, &usage);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.peak_kb = usage.ru_maxrss;
  r.out = test::read_text(log);
  return r;
}

// A file of each kind in `dir`, named with `ext` (a loader picks its parser by the extension).
struct Kind {
  std::string name;
  std::string says;  // what the message must call it
};
const std::vector<Kind> kKinds = {{"zero", "is a character device, not a regular file"},
                                  {"urandom", "is a character device, not a regular file"},
                                  {"fifo", "is a FIFO, not a regular file"},
                                  {"dir", "a directory"},
                                  {"socket", "is a socket, not a regular file"}};

class Place {
 public:
  Place() {
    dir_ = fs::temp_directory_path() / ("anamorph_kinds_" + std::to_string(getpid()));
    fs::create_directories(dir_);
  }
  ~Place() {
    for (int fd : sockets_) close(fd);
    fs::remove_all(dir_);
  }
  const fs::path& dir() const { return dir_; }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(dir_ / name) << text;
    return (dir_ / name).string();
  }
  // A file of `kind` named KIND.EXT.
  std::string make(const std::string& kind, const std::string& ext) {
    const fs::path p = dir_ / (kind + ext);
    if (fs::exists(fs::symlink_status(p))) return p.string();
    if (kind == "zero") fs::create_symlink("/dev/zero", p);
    if (kind == "urandom") fs::create_symlink("/dev/urandom", p);
    if (kind == "fifo") {
      EXPECT_EQ(mkfifo(p.c_str(), 0600), 0);
    }
    if (kind == "dir") fs::create_directories(p);
    if (kind == "socket") {
      const int fd = socket(AF_UNIX, SOCK_STREAM, 0);
      sockaddr_un a{};
      a.sun_family = AF_UNIX;
      std::snprintf(a.sun_path, sizeof a.sun_path, "%s", p.c_str());
      EXPECT_EQ(bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0) << p;
      sockets_.push_back(fd);
    }
    return p.string();
  }

 private:
  fs::path dir_;
  std::vector<int> sockets_;
};

// An input role: how a scene (or a command line) names the file.
struct Role {
  const char* name;
  const char* ext;    // the extension the file is given
  bool warns;         // a missing file is a warning by design (a model's texture), exit 0
  std::string scene;  // TOML with @F for the file, @M for a model naming it ("": the file itself)
};

const std::string kHead = "[image]\nwidth = 8\nheight = 8\n";

std::vector<Role> roles() {
  return {
      {"scene", ".toml", false, ""},
      {"include", ".toml", false, "include = \"@F\"\n"},
      {"texture", ".png", false,
       kHead + "[[material]]\nname = \"t\"\ncolor = { type = \"image\", file = \"@F\" }\n"
               "[[object]]\ntype = \"sphere\"\nmaterial = \"t\"\n"},
      {"environment", ".exr", false, kHead + "[environment]\nfile = \"@F\"\n"},
      {"ray table", ".exr", false,
       kHead + "[camera]\norg = { type = \"table\", file = \"@F\" }\n"
               "dir = { type = \"table\", file = \"@F\" }\n"},
      {"mesh (assimp)", ".obj", false, kHead + "[[object]]\ntype = \"mesh\"\nfile = \"@F\"\n"},
      {"mesh (glTF)", ".gltf", false, kHead + "[[object]]\ntype = \"mesh\"\nfile = \"@F\"\n"},
      {"mesh origin", ".obj", false,
       kHead + "[camera]\norg = { type = \"mesh\", file = \"@F\" }\n"
               "dir = { type = \"normal\" }\n"},
      {"glTF buffer", ".bin", false, kHead + "[[object]]\ntype = \"mesh\"\nfile = \"@M\"\n"},
      {"glTF image", ".png", true, kHead + "[[object]]\ntype = \"mesh\"\nfile = \"@M\"\n"},
      {"OBJ material library", ".mtl", true,
       kHead + "[[object]]\ntype = \"mesh\"\nfile = \"@M\"\n"},
  };
}

// A glTF whose buffer (or image) is `file`; an OBJ whose material library is `file`.
// (by its name, beside it: glTF URIs are relative)
std::string model_naming(Place& p, const std::string& role, const std::string& path) {
  const std::string file = fs::path(path).filename().string();
  const std::string tri =
      "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA";  // three vec3 (0 0 0, 1 0 0, 0 1 0)
  if (role == "OBJ material library")
    return p.write("with_mtl.obj", "mtllib " + file +
                                       "\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\n"
                                       "f 1 2 3\n");
  const bool image = role == "glTF image";
  const std::string buffer = image ? "data:application/octet-stream;base64," + tri : file;
  return p.write(
      image ? "with_image.gltf" : "with_buffer.gltf",
      "{\"asset\": {\"version\": \"2.0\"}, \"buffers\": [{\"uri\": \"" + buffer +
          "\", \"byteLength\": 36}], \"bufferViews\": [{\"buffer\": 0, \"byteLength\": 36}], "
          "\"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 3, \"type\": "
          "\"VEC3\", \"min\": [0, 0, 0], \"max\": [1, 1, 0]}], \"meshes\": [{\"primitives\": "
          "[{\"attributes\": {\"POSITION\": 0}, \"material\": 0}]}], \"materials\": "
          "[{\"pbrMetallicRoughness\": {\"baseColorTexture\": {\"index\": 0}}}], \"textures\": "
          "[{\"source\": 0}], \"images\": [{\"uri\": \"" +
          (image ? file : std::string("missing.png")) +
          "\"}], \"nodes\": [{\"mesh\": 0}], \"scenes\": [{\"nodes\": [0]}], \"scene\": 0}\n");
}

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  for (size_t i = s.find(from); i != std::string::npos; i = s.find(from, i + to.size()))
    s.replace(i, from.size(), to);
  return s;
}

TEST(InputKinds, EveryRoleRefusesEveryKindThatIsNotARegularFile) {
  Place p;
  for (const Role& role : roles()) {
    for (const Kind& kind : kKinds) {
      const std::string file = p.make(kind.name, role.ext);
      std::string text = replaced(role.scene, "@F", file);
      if (text.find("@M") != std::string::npos)
        text = replaced(text, "@M", model_naming(p, role.name, file));
      const std::string scene = role.scene.empty() ? file : p.write("role.toml", text);
      const Outcome r = run_bounded({"info", scene}, p.dir() / "log");
      const std::string what = std::string(role.name) + " as " + kind.name;
      EXPECT_EQ(r.code, role.warns ? 0 : 2) << what << ":\n" << r.out;
      // (the OBJ's material library is assimp's to miss, quietly: nothing to say)
      if (std::string(role.name) != "OBJ material library") {
        EXPECT_NE(r.out.find(kind.says), std::string::npos) << what << ":\n" << r.out;
      }
      // A process that reads nothing much stays well under 1 GiB (it grew to the address limit).
      EXPECT_LT(r.peak_kb, 1L << 20) << what << ": peak resident size " << r.peak_kb << " KiB";
    }
  }
}

// `compare` reads two images: the same rule.
TEST(InputKinds, CompareRefusesFilesThatAreNotRegular) {
  Place p;
  const std::string good = (test::data_dir() / "io" / "corrupt.png").string();
  for (const Kind& kind : kKinds) {
    const Outcome r = run_bounded({"compare", p.make(kind.name, ".png"), good}, p.dir() / "log");
    EXPECT_EQ(r.code, 2) << kind.name << ":\n" << r.out;
    EXPECT_NE(r.out.find(kind.says), std::string::npos) << kind.name << ":\n" << r.out;
  }
}

// `render --resume` reads a checkpoint: the same rule (a FIFO blocked in open(2)).
TEST(InputKinds, ResumeRefusesACheckpointThatIsNotRegular) {
  Place p;
  for (const Kind& kind : kKinds) {
    const Outcome r =
        run_bounded({"render", "--resume", p.make(kind.name, ".ckpt")}, p.dir() / "log");
    EXPECT_EQ(r.code, 2) << kind.name << ":\n" << r.out;
    EXPECT_NE(r.out.find(kind.says), std::string::npos) << kind.name << ":\n" << r.out;
  }
}

// A frame pattern's field width is bounded before anything is formatted (a width of a billion
// allocated 6.9 GB), for -o, --checkpoint and --stats alike.
TEST(InputKinds, FramePatternWidthIsBounded) {
  Place p;
  const std::string scene = p.write("s.toml", kHead);
  const std::string huge = (p.dir() / "out_%0999999999d.png").string();
  const std::string ok = (p.dir() / "out_%04d.png").string();
  const std::vector<std::vector<std::string>> cases = {
      {"render", scene, "--frames", "0:1", "-o", huge},
      {"render", scene, "--frames", "0:1", "-o", (p.dir() / "out_%65d.png").string()},
      {"render", scene, "--frames", "0:1", "-o", ok, "--checkpoint",
       (p.dir() / "c_%0999999999d.ckpt").string()},
      {"render", scene, "--frames", "0:1", "-o", ok, "--stats",
       (p.dir() / "s_%0999999999d.json").string()}};
  for (const auto& args : cases) {
    const Outcome r = run_bounded(args, p.dir() / "log");
    EXPECT_EQ(r.code, 2) << args.back() << ":\n" << r.out;
    EXPECT_NE(r.out.find("field width"), std::string::npos) << r.out;
    EXPECT_LT(r.peak_kb, 1L << 20) << "peak resident size " << r.peak_kb << " KiB";
  }
  EXPECT_FALSE(fs::exists(p.dir() / "out_0000.png"));
  // The widest allowed still renders.
  const Outcome wide = run_bounded(
      {"render", scene, "--frames", "0:0", "-q", "-o", (p.dir() / "w_%064d.png").string()},
      p.dir() / "log");
  EXPECT_EQ(wide.code, 0) << wide.out;
  EXPECT_TRUE(fs::exists(p.dir() / ("w_" + std::string(64, '0') + ".png")));
}

}  // namespace
}  // namespace anamorph
