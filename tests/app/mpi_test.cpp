// Rendering across MPI ranks (`mpirun -np N anamorph render`): every layer equal, bit for bit, to
// the same render in one process, for each integrator and sampling scheme; a rank killed ends the
// job without an output file, and the same command then resumes from the checkpoint.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "app/budget_runs.h"
#include "app/cli_util.h"
#include "app/same_images.h"
#include "dist/wire.h"
#include "test_util.h"

namespace anamorph {
namespace {

namespace fs = std::filesystem;
using test::join;

struct Scratch {
  fs::path dir = fs::temp_directory_path() / ("anamorph_mpi_" + std::to_string(getpid()));
  Scratch() { fs::create_directories(dir); }
  ~Scratch() { fs::remove_all(dir); }
};

bool have_mpirun() { return test::run_shell("command -v mpirun").code == 0; }

#define REQUIRE_MPI()                                                                          \
  do {                                                                                         \
    if (!ANAMORPH_HAVE_MPI) GTEST_SKIP() << "anamorph was built without MPI";                  \
    if (!have_mpirun()) GTEST_SKIP() << "mpirun not found (scripts/install-deps installs it)"; \
  } while (0)

// Open MPI's own allocations are not ours to report (sanitizer builds).
const char* kMpirun =
    "env ASAN_OPTIONS=detect_leaks=0 mpirun --allow-run-as-root --oversubscribe -x ASAN_OPTIONS "
    "-np ";

std::string example(const std::string& name) { return (test::source_dir() / name).string(); }

struct Case {
  std::vector<std::string> args;  // after `render`
  std::string ext;                // of the output
  bool aovs = false;
  std::string frames;  // "A:B": an animation, its frames compared one by one
  Case(std::vector<std::string> a, std::string e, bool with_aovs = false, std::string f = "")
      : args(std::move(a)), ext(std::move(e)), aovs(with_aovs), frames(std::move(f)) {}
};

// The render in one process and across `ranks` ranks: the same bits in every layer.
void expect_same_as_one_process(const Case& c, int ranks = 3) {
  Scratch s;
  std::vector<std::string> args{"render"};
  args.insert(args.end(), c.args.begin(), c.args.end());
  args.push_back("-q");
  if (!c.frames.empty()) args.insert(args.end(), {"--frames", c.frames});
  const std::string pattern = c.frames.empty() ? "" : "_%d";
  const std::string one = (s.dir / ("one" + pattern + c.ext)).string(),
                    many = (s.dir / ("many" + pattern + c.ext)).string();
  const test::CliResult r1 = test::run_cli(join(args) + " -o " + one, 600);
  ASSERT_EQ(r1.code, 0) << r1.out;
  const test::CliResult rn =
      test::run_shell("timeout -s KILL 600 " + std::string(kMpirun) + std::to_string(ranks) + " " +
                      test::binary().string() + " " + join(args) + " -o " + many);
  ASSERT_EQ(rn.code, 0) << rn.out;
  if (c.frames.empty()) {
    test::expect_same_outputs(one, many, c.ext, c.aovs);
    return;
  }
  const int first = std::stoi(c.frames), last = std::stoi(c.frames.substr(c.frames.find(':') + 1));
  for (int f = first; f <= last; ++f) {
    SCOPED_TRACE("frame " + std::to_string(f));
    const auto name = [&](const char* who) {
      return s.dir / (std::string(who) + "_" + std::to_string(f) + c.ext);
    };
    ASSERT_TRUE(fs::exists(name("many"))) << rn.out;
    test::expect_same_outputs(name("one"), name("many"), c.ext, c.aovs);
  }
}

TEST(Mpi, PerspectiveWhittedUniformWithAovsEqualsOneProcess) {
  REQUIRE_MPI();
  expect_same_as_one_process({{example("examples/demo.toml"), "--width", "240", "--height", "135",
                               "--spp", "4", "--aov", "albedo,normal,depth,id"},
                              ".png",
                              true});
}

TEST(Mpi, FisheyeAdaptiveLatticeEqualsOneProcess) {
  REQUIRE_MPI();
  expect_same_as_one_process(
      {{example("examples/apps/fisheye_180.toml"), "--width", "192", "--height", "192", "--set",
        "render.antialias=\"lattice\"", "--aov", "normal,spp"},
       ".exr"});
}

TEST(Mpi, PathTracingNoiseDrivenSamplingEqualsOneProcess) {
  REQUIRE_MPI();
  // Per-pixel adaptive: the head keeps the film and decides after each pass which pixels go on;
  // a pass's tiles travel with their sums and their part of the active mask.
  expect_same_as_one_process(
      {{example("examples/demo.toml"), "--width", test::side(160), "--height", test::side(90),
        "--integrator", "path", "--set", "render.antialias=\"pixel\"", "--set",
        "render.max_spp=" + std::to_string(test::spp(64)), "--aov", "albedo,spp"},
       ".exr"});
}

TEST(Mpi, PathTracingInTimedPassesEqualsOneProcess) {
  REQUIRE_MPI();
  // Uniform sampling with a time limit renders in progressive passes (not reached here).
  expect_same_as_one_process(
      {{example("examples/demo.toml"), "--width", "160", "--height", "90", "--integrator", "path",
        "--spp", "8", "--set", "render.time_limit=3600"},
       ".png"});
}

TEST(Mpi, AnimationOfFourFramesEqualsOneProcess) {
  REQUIRE_MPI();
  expect_same_as_one_process({{example("examples/apps/coin_animation.toml"), "--width",
                               test::side(160), "--height", test::side(120)},
                              ".png",
                              false,
                              "0:3"});
}

TEST(Mpi, FlowLayersOfASequenceEqualOneProcess) {
  REQUIRE_MPI();
  // Frames + 1 and - 1 are loaded on every rank: the flow (occlusion traced in the other frame),
  // motion and per-pixel ray layers of a moving fisheye with a rolling shutter and a moving ball.
  expect_same_as_one_process(
      {{example("examples/vision/sequence.toml"), "--width", "48", "--height", "48", "--aov",
        "flow_forward,flow_backward,motion,ray_origin,ray_direction"},
       ".exr",
       true,
       "1:2"},
      2);
}

TEST(Mpi, OneRankAloneRendersByItself) {
  REQUIRE_MPI();
  expect_same_as_one_process(
      {{example("examples/apps/fisheye_180.toml"), "--width", "128", "--height", "128"}, ".png"},
      1);
}

TEST(Mpi, TilesAreSpreadOverTheWorkersOnDemand) {
  REQUIRE_MPI();
  Scratch s;
  const fs::path stats = s.dir / "stats.json";
  const test::CliResult r = test::run_shell(
      "timeout -s KILL 600 " + std::string(kMpirun) + "3 " + test::binary().string() + " " +
      join({"render", example("examples/apps/domemaster.toml"), "--width", "256", "--height", "256",
            "-q", "-o", (s.dir / "dome.png").string(), "--stats", stats.string()}));
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(test::read_text(stats));
  std::map<int, int> per_rank;
  std::set<size_t> seen;
  for (const auto& t : j["tiles"]) {
    ++per_rank[t["rank"].get<int>()];
    EXPECT_TRUE(seen.insert(t["index"].get<size_t>()).second) << "tile " << t["index"] << " twice";
  }
  EXPECT_EQ(seen.size(), j["tiles_total"].get<size_t>());
  // The head hands out; the two workers render.
  EXPECT_EQ(per_rank.count(0), 0u);
  EXPECT_GT(per_rank[1], 0) << "rank 1 rendered no tile";
  EXPECT_GT(per_rank[2], 0) << "rank 2 rendered no tile";
}

// A pass render (per-pixel adaptive path tracing) under a time limit across ranks: each run
// stops handing out tiles after its budget and keeps the checkpoint (the head's film after each
// tile's pass); runs of the same resumed command go further until the render completes, with
// the bits of one uninterrupted process.
TEST(Mpi, TimeLimitedPassRenderResumesToTheSameBits) {
  REQUIRE_MPI();
  Scratch s;
  const fs::path ref = s.dir / "ref.exr", out = s.dir / "out.exr", ck = s.dir / "r.ckpt";
  const std::vector<std::string> base{
      "render",       example("examples/apps/domemaster.toml"),
      "--width",      test::side(96),
      "--height",     test::side(96),
      "--integrator", "path",
      "--set",        "render.antialias=\"pixel\"",
      "--set",        "render.max_spp=" + std::to_string(test::spp(256)),
      "--set",        "render.noise_threshold=0.005",
      "--set",        "render.tile_size=16",
      "--aov",        "albedo,spp"};
  const auto t0 = std::chrono::steady_clock::now();
  const test::CliResult r0 = test::run_cli(join(base) + " -q -o " + ref.string(), 600);
  ASSERT_EQ(r0.code, 0) << r0.out;
  // A quarter of the one-process time (start-up and loading included); three ranks may still
  // finish within it on a busy machine, so the render is started again with half the limit
  // until one run is stopped by it (at most 4 tries).
  double limit = std::max(
      0.05, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / 4);
  const std::string mpirun =
      "timeout -s KILL 600 " + std::string(kMpirun) + "3 " + test::binary().string() + " ";
  test::BudgetRuns n;
  for (int attempt = 0; attempt < 4 && n.limited == 0; ++attempt, limit /= 2) {
    fs::remove(out);
    n = {};
    const test::CliResult r =
        test::run_shell(mpirun + join(base) + " -o " + out.string() + " --checkpoint " +
                        ck.string() + " --set render.time_limit=" + std::to_string(limit));
    test::resume_until_complete(
        r, out, ck, [&] { return test::run_shell(mpirun + "render --resume " + ck.string()); }, &n);
    if (HasFatalFailure()) return;
    std::printf("%d runs of %.3f s each at most\n", n.runs, limit);
  }
  EXPECT_GE(n.limited, 1) << "no run was stopped by the time limit: the test tested nothing";
  EXPECT_FALSE(fs::exists(ck)) << "the checkpoint outlived its render";
  test::expect_same_exr(ref, out);
}

// --denoise is refused across ranks (exit 2, the reason named once, no file written) rather
// than failing inside the farm.
TEST(Mpi, DenoiseIsRefusedAcrossRanks) {
  REQUIRE_MPI();
  Scratch s;
  const fs::path out = s.dir / "many.png";
  const test::CliResult r = test::run_shell(
      "timeout -s KILL 600 " + std::string(kMpirun) + "2 " + test::binary().string() + " render " +
      example("examples/apps/fisheye_180.toml") +
      " --width 32 --height 32 --integrator path --spp 4 --denoise -q -o " + out.string());
  EXPECT_NE(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("--denoise does not run across MPI ranks"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(out));
}

TEST(Mpi, VersionNamesTheMpiLibrary) {
  const test::CliResult r = test::run_cli("--version");
  ASSERT_EQ(r.code, 0) << r.out;
  if (ANAMORPH_HAVE_MPI)
    EXPECT_NE(r.out.find("(MPI: Open MPI v"), std::string::npos) << r.out;
  else
    EXPECT_NE(r.out.find("(MPI: none)"), std::string::npos) << r.out;
}

// The pid of rank `rank` of the job whose processes carry `marker` in their environment.
pid_t find_rank(int rank, const std::string& marker) {
  const std::string want_rank = "OMPI_COMM_WORLD_RANK=" + std::to_string(rank);
  for (const auto& e : fs::directory_iterator("/proc")) {
    const std::string name = e.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    const std::string env = test::read_text(e.path() / "environ");
    bool has_rank = false, has_marker = false;
    for (size_t s = 0, z; s < env.size(); s = z + 1) {
      z = env.find('\0', s);
      if (z == std::string::npos) z = env.size();
      const std::string v = env.substr(s, z - s);
      has_rank |= v == want_rank;
      has_marker |= v == marker;
    }
    if (has_rank && has_marker) return pid_t(std::stoi(name));
  }
  return -1;
}

TEST(Mpi, KilledRankEndsTheJobAndTheSameCommandResumes) {
  REQUIRE_MPI();
  Scratch s;
  const fs::path ref = s.dir / "ref.png", out = s.dir / "out.png", ck = s.dir / "job.ckpt",
                 log = s.dir / "log";
  const std::vector<std::string> base{"render",   example("examples/apps/domemaster.toml"),
                                      "--width",  test::side(512),
                                      "--height", test::side(512),
                                      "--spp",    "16",
                                      "-q"};
  const test::CliResult r = test::run_cli(join(base) + " -o " + ref.string(), 600);
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string marker = "ANAMORPH_MPI_TEST=" + std::to_string(getpid());
  const std::string job = "timeout -s KILL 600 env " + marker + " " + kMpirun + "3 -x " +
                          "ANAMORPH_MPI_TEST " + test::binary().string() + " " + join(base) +
                          " -o " + out.string() + " --checkpoint " + ck.string();
  const pid_t pid = fork();
  if (pid == 0) {
    if (!freopen(log.c_str(), "w", stdout) || !freopen(log.c_str(), "a", stderr)) _exit(126);
    execl("/bin/sh", "sh", "-c", job.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  // Kill rank 1 once the checkpoint holds a tile (so there is something to resume from).
  uintmax_t first = 0;
  bool killed = false;
  int status = 0;
  for (;;) {
    if (waitpid(pid, &status, WNOHANG) == pid) break;
    std::error_code ec;
    const uintmax_t size = fs::file_size(ck, ec);
    if (!ec && size > 0 && first == 0) first = size;
    if (!killed && !ec && first > 0 && size > first) {
      const pid_t victim = find_rank(1, marker);
      if (victim > 0) killed = kill(victim, SIGKILL) == 0;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  const std::string said = test::read_text(log);
  if (!killed) GTEST_SKIP() << "the job finished before a rank could be killed:\n" << said;
  EXPECT_FALSE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << said;
  EXPECT_NE(said.find("rank 1"), std::string::npos) << said;
  EXPECT_FALSE(fs::exists(out)) << "an output file after a failed job";
  ASSERT_TRUE(fs::exists(ck)) << said;
  // The same command again: resumes from the tiles that were done, and ends with the same bits.
  const test::CliResult again = test::run_shell(job.substr(0, job.find(" --checkpoint")) +
                                                " --checkpoint " + ck.string() + " 2>&1");
  ASSERT_EQ(again.code, 0) << again.out;
  EXPECT_FALSE(fs::exists(ck)) << "the checkpoint outlived its render";
  test::expect_same_outputs(ref, out, ".png", false);
}

bool same_sum(const PixelSum& a, const PixelSum& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// A 3 x 2 tile at (4, 2) of a 10-pixel-wide image, with distinct sums in every pixel.
TileBuffer numbered_tile() {
  TileBuffer t(TileRect{4, 2, 7, 4}, {Aov::Albedo});
  for (size_t i = 0; i < t.sums().size(); ++i) {
    t.sums()[i].rgb[0] = float(i) + 0.25f;
    t.sums()[i].n = uint32_t(i * 3 + 1);
  }
  for (size_t i = 0; i < t.aov_sums().size(); ++i) t.aov_sums()[i] = float(i) * 0.5f + 1;
  return t;
}

// A pass tile travels with its part of the mask and the sums of only the pixels it leaves on;
// those come back into the head's tile, bit for bit, and the others stay as they were.
TEST(MpiWire, PassTilesMoveOnlyTheirActivePixels) {
  TileBuffer head = numbered_tile();
  std::vector<uint8_t> active(10 * 5, 0);
  active[2 * 10 + 5] = 1;  // (5, 2): tile pixel 1
  active[3 * 10 + 6] = 1;  // (6, 3): tile pixel 5
  active[3 * 10 + 7] = 1;  // (7, 3): outside the tile
  FarmTile t{9, head.rect(), 10, false, {4, 8, 0.125, &active}, &head};
  const std::vector<char> bytes = dist::encode_work(t, dist::mask_slice(&active, 10, t.rect));
  dist::WorkMessage m = dist::decode_work(bytes.data(), bytes.size());
  EXPECT_EQ(m.index, 9u);
  EXPECT_FALSE(m.whole);
  EXPECT_EQ(m.begin, 4u);
  EXPECT_EQ(m.end, 8u);
  EXPECT_EQ(m.footprint, 0.125);
  EXPECT_EQ(m.active, (std::vector<uint8_t>{0, 1, 0, 0, 0, 1}));
  ASSERT_EQ(m.sums.size(), 2u) << "only the active pixels' sums travel";
  TileBuffer worker(m.rect, {Aov::Albedo});
  dist::unpack_work(m, worker);
  for (size_t i = 0; i < 6; ++i) {
    const bool on = i == 1 || i == 5;
    EXPECT_TRUE(same_sum(worker.sums()[i], on ? head.sums()[i] : PixelSum{})) << i;
    EXPECT_EQ(worker.aov_sums()[i * 3], on ? head.aov_sums()[i * 3] : 0.0f) << i;
  }
  for (size_t cut : {size_t(0), size_t(10), bytes.size() - 1})
    EXPECT_THROW(dist::decode_work(bytes.data(), cut), std::runtime_error) << cut;

  // The worker's samples land on the active pixels; back at the head, only those change.
  worker.sums()[1].rgb[1] = 7;
  worker.sums()[5].spp = 99;
  worker.aov_sums()[5 * 3 + 2] = -3;
  TileStats st;
  st.rays = 123;
  st.nan(5, 3, 2);
  const std::vector<char> back = dist::encode_result(9, worker, false, m.active, st, 0.5);
  const TileBuffer before = head;
  const FarmResult r = dist::decode_result(back.data(), back.size(), {Aov::Albedo}, t, m.active);
  EXPECT_EQ(r.index, 9u);
  EXPECT_EQ(r.seconds, 0.5);
  EXPECT_EQ(r.stats.rays, 123u);
  EXPECT_EQ(r.stats.nan_x, 5);
  EXPECT_EQ(r.tile, nullptr);
  for (size_t i = 0; i < 6; ++i)
    EXPECT_TRUE(same_sum(head.sums()[i], (i == 1 || i == 5) ? worker.sums()[i] : before.sums()[i]))
        << i;
  EXPECT_EQ(head.aov_sums()[5 * 3 + 2], -3.0f);
  EXPECT_EQ(head.aov_sums()[0], before.aov_sums()[0]);
  // Read as a whole tile's result, for another tile, or with a mask of another size: refused.
  FarmTile whole = t;
  whole.whole = true;
  EXPECT_THROW(dist::decode_result(back.data(), back.size(), {Aov::Albedo}, whole),
               std::runtime_error);
  FarmTile other = t;
  other.index = 8;
  EXPECT_THROW(dist::decode_result(back.data(), back.size(), {Aov::Albedo}, other, m.active),
               std::runtime_error);
  EXPECT_THROW(dist::decode_result(back.data(), back.size(), {Aov::Albedo}, t, {1, 1}),
               std::runtime_error);

  // The first pass sends no sums (they are all zero).
  t.range.begin = 0;
  const std::vector<char> first = dist::encode_work(t, dist::mask_slice(&active, 10, t.rect));
  EXPECT_TRUE(dist::decode_work(first.data(), first.size()).sums.empty());
}

TEST(MpiWire, WholeTilesComeBackWithEveryPixelOrResolved) {
  const TileBuffer tile = numbered_tile();
  FarmTile sent;
  sent.index = 3;
  sent.rect = tile.rect();
  const std::vector<char> back = dist::encode_result(3, tile, true, {}, TileStats{}, 1.5);
  const FarmResult r = dist::decode_result(back.data(), back.size(), {Aov::Albedo}, sent);
  ASSERT_NE(r.tile, nullptr);
  EXPECT_EQ(r.tile->rect().x1, 7);
  for (size_t i = 0; i < 6; ++i) EXPECT_TRUE(same_sum(r.tile->sums()[i], tile.sums()[i])) << i;
  EXPECT_EQ(r.tile->aov_sums(), tile.aov_sums());
  // A result of other AOVs than the head's does not fit.
  EXPECT_THROW(dist::decode_result(back.data(), back.size(), {}, sent), std::runtime_error);

  // Resolved where rendered: the output's bytes, exactly as resolving at the head would give.
  // (The layers and encodings a PNG and an EXR with the albedo take.)
  const std::vector<LayerRequest> png_and_exr{
      {"", Encoding::Srgb8}, {"", Encoding::Float32}, {"albedo", Encoding::Float32}};
  sent.plan = &png_and_exr;
  const ResolvedTile local = resolve(3, tile, png_and_exr);
  const std::vector<char> bytes = dist::encode_resolved(local, tile.rect(), TileStats{}, 0.25);
  const FarmResult rr = dist::decode_result(bytes.data(), bytes.size(), {Aov::Albedo}, sent);
  ASSERT_TRUE(rr.resolved.has_value());
  EXPECT_EQ(rr.resolved->planes, local.planes);
  // Sent for a PNG only, the EXR's floats do not fit.
  const std::vector<LayerRequest> png{{"", Encoding::Srgb8}};
  sent.plan = &png;
  EXPECT_THROW(dist::decode_result(bytes.data(), bytes.size(), {Aov::Albedo}, sent),
               std::runtime_error);
}

}  // namespace
}  // namespace anamorph
