// Checkpoint and resume (`render --checkpoint`, `--resume`), interruption and --skip-existing:
// renders killed at random moments (SIGKILL: no chance to save anything but what the log already
// holds) and resumed must end bit-identical to an uninterrupted render, in every layer.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <thread>

#include "app/budget_runs.h"
#include "app/cli_util.h"
#include "app/same_images.h"
#include "io/image_io.h"
#include "render/checkpoint.h"
#include "test_util.h"

namespace anamorph {
namespace {

using test::expect_same_exr;
using test::expect_same_outputs;
using test::expect_same_png;
using test::join;

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct Scratch {
  fs::path dir = fs::temp_directory_path() / ("anamorph_ckpt_" + std::to_string(getpid()));
  Scratch() { fs::create_directories(dir); }
  ~Scratch() { fs::remove_all(dir); }
};

std::string demo_scene() { return (test::source_dir() / "examples/apps/domemaster.toml").string(); }

// Starts `anamorph ARGS` and sends it `sig` once `when()` holds (polled every 2 ms) unless it
// ended first; its exit code (-1 when killed by the signal).
int run_signalled(const std::vector<std::string>& args, const std::function<bool()>& when, int sig,
                  const fs::path& log) {
  const pid_t pid = test::spawn(args, log);
  int status = 0;
  while (!when()) {
    if (waitpid(pid, &status, WNOHANG) == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  kill(pid, sig);
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// The same, with the signal after `delay`.
int run_killed(const std::vector<std::string>& args, std::chrono::milliseconds delay, int sig,
               const fs::path& log) {
  const auto end = Clock::now() + delay;
  return run_signalled(
      args, [end] { return Clock::now() >= end; }, sig, log);
}

// Whether checkpoint `ck` holds a record besides its identity: it has grown past the size it had
// when first seen (`first`, 0 until then; the identity is written first, alone).
bool has_tile(const fs::path& ck, uintmax_t* first) {
  std::error_code ec;
  const uintmax_t size = fs::file_size(ck, ec);
  if (ec || size == 0) return false;
  if (*first == 0) *first = size;
  return size > *first;
}

struct Case {
  const char* name;
  std::vector<std::string> settings;
  std::string aovs;
};

// Renders `c` uninterrupted, then `kills` times: started with a checkpoint, SIGKILLed at a random
// moment within the reference's time, resumed by the same command (repeatedly, if the resumed
// run is killed too), and compared with the reference in every layer.
void kill_and_resume(const Case& c, const std::string& ext, int kills) {
  Scratch s;
  const fs::path ref = s.dir / ("ref" + ext), out = s.dir / ("out" + ext),
                 ck = s.dir / "render.ckpt", log = s.dir / "log";
  std::vector<std::string> base{"render", demo_scene(), "-q", "--threads", "2"};
  base.insert(base.end(), c.settings.begin(), c.settings.end());
  if (!c.aovs.empty()) base.insert(base.end(), {"--aov", c.aovs});
  std::vector<std::string> ref_args = base;
  ref_args.insert(ref_args.end(), {"-o", ref.string()});
  const auto t0 = Clock::now();
  const test::CliResult r = test::run_cli(join(ref_args), 300);
  ASSERT_EQ(r.code, 0) << r.out;
  const auto took = std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - t0);
  std::vector<std::string> args = base;
  args.insert(args.end(), {"-o", out.string(), "--checkpoint", ck.string()});
  std::mt19937 rng(12345);
  int resumed = 0;
  for (int k = 0; k < kills; ++k) {
    fs::remove(out);
    fs::remove(ck);
    // Killed at a random moment, but not before the checkpoint holds a tile (on a loaded or
    // sanitized build, startup can take most of the reference's time: a kill before any tile
    // would test nothing).
    const auto delay = std::chrono::milliseconds(std::uniform_int_distribution<int>(
        int(took.count() / 10), int(took.count() * 6 / 10))(rng));
    const auto kill_at = Clock::now() + delay;
    uintmax_t identity_size = 0;
    const auto due = [&] { return has_tile(ck, &identity_size) && Clock::now() >= kill_at; };
    const int code = run_signalled(args, due, SIGKILL, log);
    SCOPED_TRACE(fmt::format("{}: killed after {} ms (reference {} ms), exit {}", c.name,
                             delay.count(), took.count(), code));
    // Killed after its output appeared (and before it removed its checkpoint): the output is
    // complete; otherwise there is none.
    if (code == -1 && fs::exists(out)) {
      if (ext == ".exr") expect_same_exr(ref, out);
    }
    // Resumed by the same command; a second kill half-way through the rest on the first round.
    // (On a slow build the rest may take less than that: the resumed run then finishes, and
    // the run below renders again from nothing.)
    if (k == 0 && code == -1 && fs::exists(ck) && run_killed(args, delay / 2, SIGKILL, log) == 0) {
      expect_same_outputs(ref, out, ext, !c.aovs.empty());
      ++resumed;
    }
    const bool had_checkpoint = fs::exists(ck);
    std::vector<std::string> loud = args;
    loud.erase(std::find(loud.begin(), loud.end(), "-q"));
    const test::CliResult done = test::run_cli(join(loud), 300);
    ASSERT_EQ(done.code, 0) << done.out;
    if (had_checkpoint) {
      EXPECT_NE(done.out.find("resumed from"), std::string::npos) << done.out;
      std::printf("after %d ms: %s", int(delay.count()),
                  done.out.substr(0, done.out.find('\n') + 1).c_str());
      std::fflush(stdout);  // (before the next fork duplicates the buffer)
      ++resumed;
    }
    EXPECT_FALSE(fs::exists(ck)) << "the checkpoint outlived its render";
    expect_same_outputs(ref, out, ext, !c.aovs.empty());
  }
  EXPECT_GT(resumed, 0);
}

// Three kills each; one under the sanitizers, whose builds are 5-10x slower (the same code paths,
// and the suite's time is bounded).
constexpr int kKills = test::kSanitized ? 1 : 3;

TEST(Checkpoint, PathTracingUniformKilledAndResumedIsBitIdentical) {
  kill_and_resume({"path uniform",
                   {"--width", test::side(128), "--height", test::side(128), "--integrator", "path",
                    "--spp", std::to_string(test::spp(192)), "--set", "render.tile_size=16"},
                   "albedo,normal,depth,id,spp"},
                  ".exr", kKills);
}

TEST(Checkpoint, PathTracingAdaptiveKilledAndResumedIsBitIdentical) {
  kill_and_resume(
      {"path per-pixel adaptive",
       {"--width", test::side(128), "--height", test::side(128), "--integrator", "path", "--set",
        "render.antialias=\"pixel\"", "--set", "render.max_spp=" + std::to_string(test::spp(512)),
        "--set", "render.noise_threshold=0.005"},
       "albedo,normal,spp"},
      ".exr", kKills);
}

TEST(Checkpoint, WhittedLatticeKilledAndResumedIsBitIdentical) {
  kill_and_resume({"whitted lattice",
                   {"--width", test::side(768), "--height", test::side(768), "--set",
                    "render.aa_threshold=0.02", "--set", "render.tile_size=24"},
                   "normal,id"},
                  ".png", kKills);
}

// render.time_limit: each run stops at whole tiles after its budget (a quarter of the reference's
// whole-process time, so the count of runs does not depend on the build's speed), writes the image
// so far and keeps the checkpoint; `--resume` runs go further until the render completes, and the
// result is the uninterrupted render's, bit for bit.
void budget_and_resume(const Case& c, const std::string& ext) {
  Scratch s;
  const fs::path ref = s.dir / ("ref" + ext), out = s.dir / ("out" + ext), ck = s.dir / "r.ckpt";
  std::vector<std::string> base{"render", demo_scene(), "--threads", "2"};
  base.insert(base.end(), c.settings.begin(), c.settings.end());
  if (!c.aovs.empty()) base.insert(base.end(), {"--aov", c.aovs});
  auto ref_args = base;
  ref_args.insert(ref_args.end(), {"-q", "-o", ref.string()});
  const auto t0 = Clock::now();
  ASSERT_EQ(test::run_cli(join(ref_args), 300).code, 0);
  const double limit = std::max(0.05, std::chrono::duration<double>(Clock::now() - t0).count() / 4);
  auto args = base;
  args.insert(args.end(), {"-o", out.string(), "--checkpoint", ck.string(), "--set",
                           fmt::format("render.time_limit={:.3f}", limit)});
  test::BudgetRuns n;
  test::resume_until_complete(
      test::run_cli(join(args), 300), out, ck,
      [&] { return test::run_cli("render --resume " + ck.string(), 300); }, &n,
      [&](const test::CliResult& r, int run) {
        EXPECT_NE(r.out.find("continue with: anamorph render --resume " + ck.string()),
                  std::string::npos)
            << r.out;
        if (run == 1) std::printf("%s: first run: %s", c.name, r.out.c_str());
      });
  if (::testing::Test::HasFatalFailure()) return;
  std::printf("%s: %d runs of %.3f s each at most\n", c.name, n.runs, limit);
  std::fflush(stdout);
  EXPECT_GE(n.limited, 1) << "no run was stopped by the time limit: the test tested nothing";
  EXPECT_FALSE(fs::exists(ck)) << "the checkpoint outlived its render";
  expect_same_outputs(ref, out, ext, !c.aovs.empty());
}

TEST(TimeLimit, PathTracingUniformStopsAndResumesToTheSameBits) {
  budget_and_resume({"path uniform",
                     {"--width", test::side(96), "--height", test::side(96), "--integrator", "path",
                      "--spp", std::to_string(test::spp(128)), "--set", "render.tile_size=16"},
                     "albedo,normal,spp"},
                    ".exr");
}

TEST(TimeLimit, PathTracingAdaptiveStopsAndResumesToTheSameBits) {
  budget_and_resume(
      {"path per-pixel adaptive",
       {"--width", test::side(96), "--height", test::side(96), "--integrator", "path", "--set",
        "render.antialias=\"pixel\"", "--set", "render.max_spp=" + std::to_string(test::spp(256)),
        "--set", "render.noise_threshold=0.005", "--set", "render.tile_size=16"},
       "albedo,spp"},
      ".exr");
}

TEST(TimeLimit, WhittedLatticeStopsAndResumesToTheSameBits) {
  budget_and_resume({"whitted lattice",
                     {"--width", test::side(512), "--height", test::side(512), "--set",
                      "render.aa_threshold=0.02", "--set", "render.tile_size=16"},
                     "normal"},
                    ".png");
}

// A time limit without a checkpoint: the image so far is the result, and the user is told how to
// be able to continue next time.
TEST(TimeLimit, WithoutCheckpointTheImageSoFarIsTheResult) {
  Scratch s;
  const fs::path out = s.dir / "out.png";
  const test::CliResult r = test::run_cli(
      "render " + demo_scene() +
          " --width 96 --height 96 --integrator path --spp 100000 --set render.time_limit=0.3 "
          "--threads 2 -o " +
          out.string(),
      300);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("time limit of 0.3 s reached after"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("render with --checkpoint FILE to be able to continue"), std::string::npos)
      << r.out;
  // Progressive passes: the first (1 sample a pixel) covers the frame, so every pixel inside the
  // domemaster's image circle has samples.
  const Image img = read_image(out, false);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const double dx = x + 0.5 - img.width / 2.0, dy = y + 0.5 - img.height / 2.0;
      if (std::hypot(dx, dy) >= 0.45 * img.width) continue;
      ASSERT_GT(img.pixels[(size_t(y) * size_t(img.width) + size_t(x)) * 4 + 3], 0.0f)
          << "pixel " << x << "," << y << " has no samples";
    }
}

// SIGINT: the image so far beside the output, a checkpoint, exit 3; --resume finishes it.
TEST(Checkpoint, InterruptWritesTheImageSoFarAndResumeFinishes) {
  Scratch s;
  const fs::path ref = s.dir / "ref.png", out = s.dir / "out.png", ck = s.dir / "r.ckpt";
  const std::string spp = std::to_string(test::spp(256));
  const std::vector<std::string> base{
      "render",       demo_scene(), "-q",    "--width", "128",       "--height", "128",
      "--integrator", "path",       "--spp", spp,       "--threads", "2"};
  auto ref_args = base;
  ref_args.insert(ref_args.end(), {"-o", ref.string()});
  const auto t0 = Clock::now();
  ASSERT_EQ(test::run_cli(join(ref_args), 300).code, 0);
  const auto took = std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - t0);
  auto args = base;
  args.insert(args.end(), {"-o", out.string(), "--checkpoint", ck.string()});
  const int code = run_killed(args, took / 2, SIGINT, s.dir / "log");
  const std::string log = test::read_text(s.dir / "log");
  ASSERT_EQ(code, 3) << log;
  EXPECT_NE(log.find("the image so far is in " + (s.dir / "out.partial.png").string()),
            std::string::npos)
      << log;
  EXPECT_NE(log.find("anamorph render --resume " + ck.string()), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(out));
  ASSERT_TRUE(fs::exists(s.dir / "out.partial.png"));
  // The image so far: some tiles rendered (opaque), the rest transparent.
  const Image partial = read_image(s.dir / "out.partial.png", false);
  size_t opaque = 0, clear = 0;
  for (size_t i = 3; i < partial.pixels.size(); i += 4) (partial.pixels[i] > 0 ? opaque : clear)++;
  EXPECT_GT(opaque, 0u);
  EXPECT_GT(clear, 0u);
  const test::CliResult done = test::run_cli("render --resume " + ck.string(), 300);
  ASSERT_EQ(done.code, 0) << done.out;
  expect_same_png(ref, out);
  EXPECT_FALSE(fs::exists(ck));
  EXPECT_FALSE(fs::exists(s.dir / "out.partial.png")) << "a finished render keeps no partial image";
}

// A checkpoint of another render is refused, naming what changed; a damaged one too.
TEST(Checkpoint, ChangedSceneOrSettingsAreRefused) {
  Scratch s;
  const fs::path out = s.dir / "out.png", ck = s.dir / "r.ckpt";
  const std::string spp = std::to_string(test::spp(512)), half = std::to_string(test::spp(256));
  const std::string base = "render " + demo_scene() +
                           " -q --width 96 --height 96 --integrator path --spp " + spp + " -o " +
                           out.string() + " --checkpoint " + ck.string();
  // Interrupted once the checkpoint holds a tile besides its identity (whatever the build's
  // speed), so that cutting its end below leaves good records.
  uintmax_t identity_size = 0;
  const auto tile_written = [&] { return has_tile(ck, &identity_size); };
  ASSERT_EQ(run_signalled(
                {"render", demo_scene(), "-q", "--width", "96", "--height", "96", "--integrator",
                 "path", "--spp", spp, "-o", out.string(), "--checkpoint", ck.string()},
                tile_written, SIGINT, s.dir / "log"),
            3)
      << test::read_text(s.dir / "log");
  const test::CliResult other = test::run_cli(
      "render " + demo_scene() + " -q --width 96 --height 96 --integrator path --spp " + half +
      " -o " + out.string() + " --checkpoint " + ck.string());
  EXPECT_EQ(other.code, 2) << other.out;
  EXPECT_NE(other.out.find("render.spp was " + spp + ", is " + half), std::string::npos)
      << other.out;
  const test::CliResult fov = test::run_cli(base + " --set camera.fov=170");
  EXPECT_EQ(fov.code, 2) << fov.out;
  EXPECT_NE(fov.out.find("camera.fov"), std::string::npos) << fov.out;
  EXPECT_FALSE(fs::exists(out));
  std::ofstream(s.dir / "junk.ckpt") << "not a checkpoint";
  const test::CliResult junk = test::run_cli("render --resume " + (s.dir / "junk.ckpt").string());
  EXPECT_EQ(junk.code, 2) << junk.out;
  EXPECT_NE(junk.out.find("is not an anamorph checkpoint"), std::string::npos) << junk.out;
  // Cut in the middle of a record: the good records before it still count.
  fs::resize_file(ck, fs::file_size(ck) - 7);
  const test::CliResult cut = test::run_cli(base);
  EXPECT_EQ(cut.code, 0) << cut.out;
  EXPECT_TRUE(fs::exists(out));
}

// A checkpoint records the build that made it (a hash of the program): another build's checkpoint
// is refused, saying so, and one without a build (older) too; the same build resumes it.
TEST(Checkpoint, AnotherBuildsCheckpointIsRefused) {
  Scratch s;
  const fs::path out = s.dir / "out.png", ck = s.dir / "r.ckpt";
  const std::vector<std::string> args = {"render",
                                         demo_scene(),
                                         "-q",
                                         "--width",
                                         "64",
                                         "--height",
                                         "64",
                                         "--integrator",
                                         "path",
                                         "--spp",
                                         std::to_string(test::spp(512)),
                                         "-o",
                                         out.string(),
                                         "--checkpoint",
                                         ck.string()};
  uintmax_t identity_size = 0;
  ASSERT_EQ(run_signalled(
                args, [&] { return has_tile(ck, &identity_size); }, SIGINT, s.dir / "log"),
            3)
      << test::read_text(s.dir / "log");
  const std::string good = test::read_text(ck);
  CheckpointIdentity id = CheckpointReader(ck).identity();
  const auto build = std::find_if(id.begin(), id.end(), [](auto& e) { return e.first == "build"; });
  ASSERT_NE(build, id.end()) << "no build in the checkpoint's identity";
  // The program's GNU build ID, as readelf shows it (when the tool is there).
  const test::CliResult readelf =
      test::run_shell("readelf -n " + std::string(ANAMORPH_BINARY) + " 2>/dev/null");
  if (readelf.out.find("Build ID: ") != std::string::npos) {
    EXPECT_CONTAINS(readelf.out, "Build ID: " + build->second);
  }
  const std::string mine = build->second;
  std::string cmd;
  for (const std::string& a : args) cmd += (cmd.empty() ? "" : " ") + a;
  // Forged: the same render from another build, then from one that recorded none.
  build->second = "0123456789abcdef-1";
  { CheckpointWriter(ck, id, 1e9); }
  const test::CliResult other = test::run_cli(cmd);
  EXPECT_EQ(other.code, 2) << other.out;
  EXPECT_CONTAINS(
      other.out,
      "made by another build of anamorph (build 0123456789abcdef-1, this one is " + mine + ")");
  EXPECT_FALSE(fs::exists(out));
  id.erase(build);
  { CheckpointWriter(ck, id, 1e9); }
  const test::CliResult none = test::run_cli(cmd);
  EXPECT_EQ(none.code, 2) << none.out;
  EXPECT_CONTAINS(none.out, "(build not recorded, this one is " + mine + ")");
  std::ofstream(ck, std::ios::binary | std::ios::trunc) << good;
  const test::CliResult same = test::run_cli(cmd);
  EXPECT_EQ(same.code, 0) << same.out;
  EXPECT_TRUE(fs::exists(out));
}

// --frames with --skip-existing renders only the frames that are not there yet; a frame file
// appears only when complete.
TEST(Checkpoint, SkipExistingRendersOnlyMissingFrames) {
  Scratch s;
  const std::string scene = (s.dir / "anim.toml").string();
  std::ofstream(scene) << "[image]\nwidth = 16\nheight = 16\n[camera]\nlook_from = [0, 1, 4]\n"
                          "look_at = [0, 0, 0]\n[[object]]\ntype = \"sphere\"\n[[animate]]\n"
                          "key = \"camera.fov\"\nkeys = [[0, 30], [3, 60]]\n";
  const std::string pattern = (s.dir / "f_%d.png").string();
  ASSERT_EQ(test::run_cli("render " + scene + " -q --frames 1:1 -o " + pattern).code, 0);
  const auto before = fs::last_write_time(s.dir / "f_1.png");
  const test::CliResult r =
      test::run_cli("render " + scene + " --frames 0:3 --skip-existing -o " + pattern);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("f_1.png exists: skipped"), std::string::npos) << r.out;
  EXPECT_EQ(fs::last_write_time(s.dir / "f_1.png"), before);
  for (int f = 0; f < 4; ++f) EXPECT_TRUE(fs::exists(s.dir / ("f_" + std::to_string(f) + ".png")));
  const test::CliResult bad = test::run_cli("render " + scene + " --frames 0:3 -o " + pattern +
                                            " --checkpoint " + (s.dir / "one.ckpt").string());
  EXPECT_EQ(bad.code, 2) << bad.out;
  EXPECT_NE(bad.out.find("needs a frame-number pattern"), std::string::npos) << bad.out;
}

}  // namespace
}  // namespace anamorph
