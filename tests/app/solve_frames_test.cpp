// `anamorph solve --frames A:B`: a pin whose target is keyed to move linearly over three frames,
// the camera's look_at free. Each frame of the written scene (its [[animate]] keys) re-projects
// the pin where it was keyed, checked with `anamorph project --frame` (not the solver's numbers);
// each frame starts from the previous frame's solution and the solution moves evenly; a frame
// whose goal cannot be met is named, exit 2, nothing written.
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

const char* kKeyedPin =
    "# a pin keyed to move\n[image]\nwidth = 320\nheight = 240\n[camera]\n"
    "look_from = [0, 1, 5]\nlook_at = [0, 0, 0]\nfov = 40\n"
    "[[camera.free]]\nkey = \"camera.look_at.0\"\n[[camera.free]]\nkey = \"camera.look_at.1\"\n"
    "[[camera.constraint]]\nkind = \"pin\"\npoint = [1, 0, 0]\nuv = [0.6, 0.5]\n"
    "tolerance = 1e-6\n[[animate]]\nkey = \"camera.constraint.0.uv\"\n"
    "keys = [[0, [0.6, 0.5]], [2, [0.7, 0.45]]]\n";

// Each "NAME start -> value" line solve printed for `name`, in order: {start, value}.
std::vector<std::pair<double, double>> printed_values(const std::string& out,
                                                      const std::string& name) {
  std::vector<std::pair<double, double>> v;
  const std::regex re(std::regex_replace(name, std::regex(R"(\.)"), R"(\.)") +
                      R"( +(\S+) -> (\S+))");
  for (auto it = std::sregex_iterator(out.begin(), out.end(), re); it != std::sregex_iterator();
       ++it)
    v.emplace_back(std::stod((*it)[1].str()), std::stod((*it)[2].str()));
  return v;
}

TEST(SolveFrames, AKeyedPinIsFollowedFrameByFrameFromThePreviousSolution) {
  test::ScratchDir dir("solve_frames");
  const std::string scene = dir.write("s.toml", kKeyedPin);
  const std::string solved = (dir.dir / "solved.toml").string();
  const CliResult r =
      test::run_cli(fmt::format("solve '{}' --frames 0:2 -o '{}'", scene, solved), 60);
  ASSERT_EQ(r.code, 0) << r.out;
  // Each frame of the written scene puts the pin where it is keyed (linear: uv(1) is halfway).
  const double want[3][2] = {{0.6, 0.5}, {0.65, 0.475}, {0.7, 0.45}};
  for (int f = 0; f < 3; ++f) {
    const CliResult p =
        test::run_cli(fmt::format("project '{}' --frame {} --point 1,0,0", solved, f), 60);
    double x = NAN, y = NAN;
    ASSERT_EQ(std::sscanf(p.out.c_str(), "px %lf py %lf", &x, &y), 2) << p.out;
    EXPECT_NEAR(x, want[f][0] * 320, 1e-6) << "frame " << f;
    EXPECT_NEAR(y, want[f][1] * 240, 1e-6) << "frame " << f;
  }
  // Frame 0 starts from the scene's values, each later frame from the previous solution (to the
  // 9 digits printed), and the solution moves evenly: the two steps differ by under 5 % (the
  // target moves linearly; the measured difference is about 2 %).
  for (const char* name : {"camera.look_at.0", "camera.look_at.1"}) {
    const auto v = printed_values(r.out, name);
    ASSERT_EQ(v.size(), 3u) << r.out;
    EXPECT_EQ(v[0].first, 0) << name;
    for (int f = 1; f < 3; ++f)
      EXPECT_NEAR(v[f].first, v[f - 1].second, 1e-8 * (1 + std::abs(v[f].first))) << name;
    const double d01 = v[1].second - v[0].second, d12 = v[2].second - v[1].second;
    EXPECT_LT(std::abs(d12 - d01), 0.05 * std::abs(d01)) << name << ": " << d01 << ", " << d12;
  }
  const std::string text = test::read_text(solved);
  EXPECT_NE(text.find("# a pin keyed to move\n"), std::string::npos) << text;
  EXPECT_NE(text.find("key = \"camera.look_at\""), std::string::npos) << text;
  // Deterministic: the same run writes the same bytes.
  const std::string again = (dir.dir / "again.toml").string();
  ASSERT_EQ(test::run_cli(fmt::format("solve '{}' --frames 0:2 -o '{}'", scene, again), 60).code,
            0);
  EXPECT_EQ(test::read_text(again), text);
}

TEST(SolveFrames, AFrameWhoseGoalCannotBeMetIsNamedAndNothingIsWritten) {
  test::ScratchDir dir("solve_frames_unmet");
  // Only the fov is free and the pinned point lies on the horizontal mid-line: frame 1's target
  // below it cannot be reached.
  const std::string scene = dir.write(
      "s.toml",
      "[image]\nwidth = 320\nheight = 240\n[camera]\nlook_from = [0, 0, 5]\n"
      "look_at = [0, 0, 0]\nfov = 40\n[[camera.free]]\nkey = \"camera.fov\"\n"
      "[[camera.constraint]]\nkind = \"pin\"\npoint = [1, 0, 0]\nuv = [0.6, 0.5]\n"
      "[[animate]]\nkey = \"camera.constraint.0.uv\"\nkeys = [[0, [0.6, 0.5]], [1, [0.6, 0.3]]]\n");
  const fs::path out = dir.dir / "solved.toml";
  const CliResult r =
      test::run_cli(fmt::format("solve '{}' --frames 0:1 -o '{}'", scene, out.string()), 60);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("frame 1: constraints not met"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("cannot be met even alone"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(out));
  const CliResult bad = test::run_cli(fmt::format("solve '{}' --frames 2:1", scene), 60);
  EXPECT_EQ(bad.code, 2) << bad.out;
  EXPECT_NE(bad.out.find("--frames 2:1"), std::string::npos) << bad.out;
}

}  // namespace
}  // namespace anamorph
