// `anamorph solve`: known answers recovered (a perspective camera's look_at and fov from pins it
// made; a coin's strength and radius from its magnification and a pin), the solved scene checked
// by `anamorph project` (not by the solver's own numbers), conflicts and unreachable goals named
// with exit 2 and nothing written, bounds kept, the scene's comments kept, bad goals refused.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <regex>
#include <string>
#include <vector>

#include "cli_util.h"
#include "run_fixture.h"
#include "solve_util.h"
#include "test_util.h"

namespace anamorph {
namespace {

namespace fs = std::filesystem;
using test::CliResult;
using test::numbers_of;
using test::printed_residual;
using test::projected;

#define EXPECT_CONTAINS(hay, needle) \
  EXPECT_NE(std::string(hay).find(needle), std::string::npos) << "output was:\n" << (hay)

const char* kImage = "[image]\nwidth = 320\nheight = 240\n";

// Pins [[camera.constraint]] of `points` where `truth` shows them (through `anamorph project`).
std::string pins(const std::string& truth, const std::vector<std::vector<double>>& points) {
  std::string t;
  for (const auto& p : points) {
    const std::vector<double> px = projected(truth, p);
    t += fmt::format(
        "[[camera.constraint]]\nkind = \"pin\"\npoint = [{}, {}, {}]\nuv = [{}, {}]\n"
        "tolerance = 0.001\n",
        p[0], p[1], p[2], px[0] / 320, px[1] / 240);
  }
  return t;
}

const std::vector<std::vector<double>> kPoints = {{1, 0, 0}, {-1, 0.5, 0}, {0.5, -0.5, 1}};

TEST(SolveCli, RecoversLookAtAndFovFromPinsOfAKnownCamera) {
  test::ScratchDir dir("solve_pose");
  const std::string truth = dir.write(
      "truth.toml",
      std::string(kImage) + "[camera]\nlook_from = [0, 1, 5]\nlook_at = [0.3, 0.2, 0]\nfov = 52\n");
  const std::string start =
      dir.write("start.toml",
                std::string(kImage) +
                    "# the start\n[camera]\nlook_from = [0, 1, 5]\nlook_at = [0, 0, 0]  # solved\n"
                    "fov = 40\n[[camera.free]]\nkey = \"camera.fov\"\n[[camera.free]]\n"
                    "key = \"camera.look_at.0\"\n[[camera.free]]\nkey = \"camera.look_at.1\"\n" +
                    pins(truth, kPoints));
  const std::string solved = (dir.dir / "solved.toml").string();
  const CliResult r = test::run_cli(fmt::format("solve '{}' -o '{}'", start, solved), 60);
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string text = test::read_text(solved);
  const std::vector<double> fov = numbers_of(text, "fov"), at = numbers_of(text, "look_at");
  ASSERT_EQ(fov.size(), 1u);
  ASSERT_EQ(at.size(), 3u);
  EXPECT_NEAR(fov[0], 52, 1e-6);
  EXPECT_NEAR(at[0], 0.3, 1e-6);
  EXPECT_NEAR(at[1], 0.2, 1e-6);
  EXPECT_EQ(at[2], 0);
  EXPECT_CONTAINS(text, "# the start\n");  // the scene's own text, comments kept
  EXPECT_CONTAINS(text, "  # solved\n");
  // Every pin re-projects through the solved scene within the residual solve reported (the
  // printed pixels have 6 decimals).
  for (size_t i = 0; i < kPoints.size(); ++i) {
    const std::vector<double> want = projected(truth, kPoints[i]),
                              got = projected(solved, kPoints[i]);
    EXPECT_LE(std::hypot(got[0] - want[0], got[1] - want[1]),
              printed_residual(r.out, int(i)) + 2e-6)
        << "pin " << i << ": " << got[0] << ", " << got[1] << " vs " << want[0] << ", " << want[1];
  }
  // Deterministic: the same run writes the same bytes.
  const std::string again = (dir.dir / "again.toml").string();
  ASSERT_EQ(test::run_cli(fmt::format("solve '{}' -o '{}'", start, again), 60).code, 0);
  EXPECT_EQ(test::read_text(again), text);
}

TEST(SolveCli, RecoversACoinsStrengthAndRadiusFromMagnificationAndAPin) {
  test::ScratchDir dir("solve_coin");
  const std::string camera =
      "[camera]\nlook_from = [0, 2.2, 6]\nlook_at = [0, 0, 0]\nfov = 55\n[[camera.coin]]\n"
      "position = [0.9, 0, 0.4]\naffects = \"dir\"\n";
  const std::string truth =
      dir.write("truth.toml", kImage + camera + "strength = 0.6\nradius = 0.22\n");
  // (strength m magnifies the coin's centre by 1 / (1 - m) with affects = "dir": 2.5 at 0.6)
  const std::string start = dir.write(
      "start.toml",
      kImage + camera +
          "strength = 0.3\nradius = 0.3\n[[camera.free]]\nkey = \"camera.coin.0.strength\"\n"
          "[[camera.free]]\nkey = \"camera.coin.0.radius\"\n[[camera.constraint]]\n"
          "kind = \"magnification\"\npoint = [0.9, 0, 0.4]\nmagnification = 2.5\n"
          "tolerance = 0.001\n" +
          pins(truth, {{1.2, 0.1, 0.4}}));
  const std::string solved = (dir.dir / "solved.toml").string();
  const CliResult r = test::run_cli(fmt::format("solve '{}' -o '{}'", start, solved), 60);
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string text = test::read_text(solved);
  EXPECT_NEAR(numbers_of(text, "strength").at(0), 0.6, 1e-4);
  EXPECT_NEAR(numbers_of(text, "radius").at(0), 0.22, 1e-4);
  const std::vector<double> want = projected(truth, {1.2, 0.1, 0.4}),
                            got = projected(solved, {1.2, 0.1, 0.4});
  EXPECT_LE(std::hypot(got[0] - want[0], got[1] - want[1]), printed_residual(r.out, 1) + 2e-6);
}

const char* kFovOnly =
    "[camera]\nlook_from = [0, 1, 5]\nlook_at = [0, 0, 0]\nfov = 40\n[[camera.free]]\n"
    "key = \"camera.fov\"\nmin = 10\nmax = {}\n"
    "[[camera.constraint]]\nkind = \"pin\"\npoint = [1, 0, 0]\nuv = [0.7, 0.5]\n"
    "[[camera.constraint]]\nkind = \"pin\"\npoint = [1, 0, 0]\nuv = [0.6, 0.5]\n"
    "[[camera.constraint]]\nkind = \"pin\"\npoint = [0, 0, 0]\nuv = [0.5, 0.5]\n";

TEST(SolveCli, ConflictingPinsAreNamedAndNothingIsWritten) {
  test::ScratchDir dir("solve_conflict");
  const std::string scene = dir.write("s.toml", kImage + fmt::format(fmt::runtime(kFovOnly), 120));
  const fs::path out = dir.dir / "solved.toml";
  const CliResult r = test::run_cli(fmt::format("solve '{}' -o '{}'", scene, out.string()), 60);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_CONTAINS(r.out, "camera.constraint[0] (pin): conflicts with camera.constraint[1]");
  EXPECT_CONTAINS(r.out, "camera.constraint[1] (pin): conflicts with camera.constraint[0]");
  EXPECT_EQ(r.out.find("camera.constraint[2] (pin)"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(out));
}

TEST(SolveCli, BoundsAreKeptAndAGoalOutOfReachIsSaidSo) {
  test::ScratchDir dir("solve_bounds");
  // Pin 0 needs a fov of about 52 degrees: the bound 45 holds it back.
  const std::string scene = dir.write("s.toml", kImage + fmt::format(fmt::runtime(kFovOnly), 45));
  const CliResult r = test::run_cli(fmt::format("solve '{}'", scene), 60);
  EXPECT_EQ(r.code, 2) << r.out;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.out, m, std::regex(R"(camera\.fov +\S+ -> (\S+))"))) << r.out;
  EXPECT_EQ(std::stod(m[1].str()), 45) << r.out;
  EXPECT_CONTAINS(r.out, "at its bound");
  EXPECT_CONTAINS(r.out, "camera.constraint[0] (pin): cannot be met even alone");
}

TEST(SolveCli, BadGoalsAndOutputsExit2Named) {
  test::ScratchDir dir("solve_bad");
  const std::string pin =
      "[[camera.constraint]]\nkind = \"pin\"\npoint = [1, 0, 0]\nuv = [0.6, 0.5]\n";
  const std::string base = std::string(kImage) + "[camera]\nfov = 40\n";
  struct Case {
    std::string text, expect;
  };
  const Case cases[] = {
      {base + "[[camera.free]]\nkey = \"camera.preset\"\n" + pin, "a string: only numbers"},
      {base + "[[camera.free]]\nkey = \"camera.nothing\"\n" + pin, "not a declared key"},
      {base + "[[camera.free]]\nkey = \"image.width\"\n" + pin, "only camera keys"},
      {base + "[[camera.free]]\nkey = \"camera.fov\"\n", "no [[camera.constraint]]"},
      {base + pin, "no [[camera.free]]"},
      {base + "[[camera.free]]\nkey = \"camera.fov\"\n" + pin + "colour = 1\n", "colour"},
      {base + "[[camera.free]]\nkey = \"camera.fov\"\n[[camera.constraint]]\nkind = \"pin\"\n"
              "object = \"nobody\"\nuv = [0.5, 0.5]\n",
       "no object \"nobody\""},
  };
  for (const Case& c : cases) {
    const std::string scene = dir.write("bad.toml", c.text);
    const CliResult r = test::run_cli(fmt::format("solve '{}'", scene), 60);
    EXPECT_EQ(r.code, 2) << c.text << "\n" << r.out;
    EXPECT_CONTAINS(r.out, c.expect);
  }
  // The scene itself as -o: refused by the output guard, the scene unchanged.
  const std::string text = base + "[[camera.free]]\nkey = \"camera.fov\"\n" + pin;
  const std::string scene = dir.write("s.toml", text);
  const CliResult r = test::run_cli(fmt::format("solve '{}' -o '{}'", scene, scene), 60);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_EQ(test::read_text(scene), text);
  // Other commands check the goals too.
  const std::string typo = dir.write("typo.toml", base + pin + "uvv = [0, 0]\n");
  const CliResult info = test::run_cli(fmt::format("info '{}'", typo), 60);
  EXPECT_EQ(info.code, 2) << info.out;
  EXPECT_CONTAINS(info.out, "uvv");
}

}  // namespace
}  // namespace anamorph
