// The second probe's crashes (issue 32, part 2), each from the command line as the user met it:
// once a signal (SIGABRT from Embree's asserts, SIGSEGV from a stack overflow or a thread count),
// now exit code 2 with the file, line, column and key, or a render that completes. (The editor's
// and Python's sides: depth_limit_test.cpp, coordinate_range_test.cpp, below, and
// python/tests/test_limits.py; the truncated checkpoint: tests/app/checkpoint_damage_test.cpp.)
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <string>

#include "app/cli_util.h"
#include "io/image_io.h"
#include "server/server_fixture.h"

namespace anamorph::test {
namespace {

const std::string kHead =
    "[image]\nwidth = 16\nheight = 12\n[render]\nintegrator = \"whitted\"\n"
    "[[material]]\nname = \"m\"\nreflectivity = 0.5\n";

struct Case {
  const char* name;
  std::string scene;       // after kHead
  std::string says;        // in the message, after "crash.toml:"
  std::string extra = "";  // more arguments
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

class Crash : public ::testing::TestWithParam<Case> {};

TEST_P(Crash, IsALocatedErrorWithExitCode2) {
  const Case& c = GetParam();
  TempFolder dir;
  const fs::path scene = dir.write("crash.toml", kHead + c.scene);
  const CliResult r = run_cli(fmt::format("render {} -q -o {} {}", scene.string(),
                                          (dir.path() / "out.png").string(), c.extra),
                              120);
  EXPECT_EQ(r.code, 2) << r.out.substr(0, 1000);
  EXPECT_NE(r.out.find("crash.toml:" + c.says), std::string::npos) << r.out.substr(0, 1000);
  EXPECT_FALSE(fs::exists(dir.path() / "out.png"));
}

std::string parts(int n, const std::string& sep) {
  std::string s = "a";
  for (int i = 1; i < n; ++i) {  // (not `sep + "a"`: GCC 12 warns, wrongly, of an overlap)
    s += sep;
    s += 'a';
  }
  return s;
}

// An EXR ray table (layers org and dir, 2 x 2 samples) with the origins and directions given.
fs::path ray_table(const TempFolder& dir, const std::string& name, float org, float dir_x) {
  OutputImage img;
  img.width = img.height = 2;
  img.layers.push_back({"", {"R", "G", "B", "A"}, std::vector<float>(16, 1.f)});
  img.layers.push_back({"org", {"X", "Y", "Z"}, std::vector<float>(12, org)});
  std::vector<float> d(12, 0.f);
  for (size_t i = 0; i < 4; ++i) d[3 * i] = dir_x, d[3 * i + 2] = dir_x == 0 ? 0.f : -1.f;
  img.layers.push_back({"dir", {"X", "Y", "Z"}, d});
  const fs::path p = dir.path() / name;
  write_exr(p, img);
  return p;
}

INSTANTIATE_TEST_SUITE_P(
    SecondProbe, Crash,
    ::testing::Values(
        Case{"LookFromAt2e18",
             "[camera]\nlook_from = [2e18, 1, 4]\nlook_at = [0, 0, 0]\n[[object]]\n"
             "type = \"sphere\"\n",
             "10:14: camera.look_from: value 2e+18 is out of range"},
        Case{"PlaneAt1e30",
             "[[object]]\ntype = \"plane\"\npoint = [0, 1e30, 0]\n[[light]]\ntype = \"point\"\n",
             "11:13: object[0].point: value 1e+30 is out of range"},
        Case{"HugeSphere", "[[object]]\ntype = \"sphere\"\nradius = 1e30\n",
             "11:10: object[0].radius: value 1e+30 is out of range"},
        Case{"SphereReachingBeyondTheWorld",
             "[[object]]\ntype = \"sphere\"\ncenter = [9e11, 0, 0]\nradius = 9e11\n",
             "12:10: object[0].radius: it reaches |x| = 1.8e+12"},
        Case{"TransformedBeyondTheWorld",
             "[[object]]\ntype = \"box\"\ntransform = { scale = 1e6, translate = [0, 0, 1e12] }\n"
             "size = [1e6, 1, 1]\n",
             "11:13: object[0].transform: it reaches |z| = 1e+12"},
        Case{"ScatteredSurfaceAt1e19",
             "[camera.org]\ntype = \"scattered\"\npoints = [[0, 0, 1e19, 0, 0], [1, 0, 0, 1, 0], "
             "[0, 1, 0, 0, 1]]\n[camera.dir]\ntype = \"normal\"\n",
             "11:10: camera.org.points: point 0: [1e+19, 0, 0] is not within"},
        Case{"InlineRayTableWithAHugeOrigin",
             "[camera.org]\ntype = \"table\"\nsamples = [[[0, 0, 0], [3e18, 0, 0]]]\n"
             "[camera.dir]\ntype = \"table\"\nsamples = [[[0, 0, -1], [0, 0, -1]]]\n",
             "11:25: camera.org.samples: value 3e+18 is out of range"},
        Case{"InlineRayTableOfZeroDirections",
             "[camera.org]\ntype = \"table\"\nsamples = [[[0, 0, 0], [1, 0, 0]]]\n"
             "[camera.dir]\ntype = \"table\"\nsamples = [[[0, 0, 0], [0, 0, 0]]]\n",
             "14:11: camera.dir.samples: the table has no valid sample"},
        Case{"DottedKeyOf50000Parts", parts(50000, ".") + " = 1\n",
             "9:1: TOML syntax error: nested more than 64 levels deep"},
        Case{"HeaderOf100000Parts", std::string(1, '[').append(parts(100000, ".")) + "]\n",
             "9:2: TOML syntax error: nested more than 64 levels deep"}),
    [](const ::testing::TestParamInfo<Case>& i) { return i.param.name; });

// Ray tables in EXR files: origins beyond the world are an error at the file key; directions of
// zero length are samples without a ray, and a table of nothing else has no valid sample.
TEST(CrashFiles, RayTableFilesWithHugeOriginsOrZeroDirectionsAreLocatedErrors) {
  TempFolder dir;
  const fs::path huge = ray_table(dir, "huge.exr", 2e18f, 0.f);
  const fs::path zero = ray_table(dir, "zero.exr", 0.f, 0.f);
  const fs::path fine = ray_table(dir, "fine.exr", 0.f, 0.1f);
  const auto render = [&](const fs::path& org, const fs::path& dir_file) {
    const fs::path scene = dir.write(
        "t.toml", fmt::format("{}[camera.org]\ntype = \"table\"\nfile = \"{}\"\n[camera.dir]\n"
                              "type = \"table\"\nfile = \"{}\"\n",
                              kHead, org.string(), dir_file.string()));
    return run_cli(
        fmt::format("render {} -q -o {}", scene.string(), (dir.path() / "t.png").string()), 120);
  };
  const CliResult h = render(huge, fine);
  EXPECT_EQ(h.code, 2) << h.out;
  EXPECT_NE(h.out.find("t.toml:11:8: camera.org.file: sample (0, 0) at [2e+18, 2e+18, 2e+18] "
                       "lies beyond"),
            std::string::npos)
      << h.out;
  const CliResult z = render(fine, zero);
  EXPECT_EQ(z.code, 2) << z.out;
  EXPECT_NE(z.out.find("t.toml:14:8: camera.dir.file: the table has no valid sample"),
            std::string::npos)
      << z.out;
  const CliResult f = render(fine, fine);
  EXPECT_EQ(f.code, 0) << f.out;
}

// A plane within the world seen at a grazing angle: hits beyond the world are not hits, so no
// shadow or mirror ray starts out there (a plane at 1e11 made Embree assert on a shadow ray
// from 1e30 before the bound).
TEST(CrashFiles, AGrazingPlaneRendersWithItsShadowAndMirrorRays) {
  TempFolder dir;
  const fs::path scene =
      dir.write("grazing.toml", kHead +
                                    "[camera]\nlook_from = [0, 0, 0]\nlook_at = [0, 1, -1000]\n"
                                    "[[object]]\ntype = \"plane\"\nmaterial = \"m\"\n"
                                    "point = [0, 1e11, 0]\nnormal = [0, -1, 0]\n"
                                    "[[object]]\ntype = \"sphere\"\ncenter = [0, 1, -5]\n"
                                    "[[light]]\ntype = \"point\"\nposition = [0, 5, 0]\n");
  const fs::path out = dir.path() / "g.png";
  const CliResult r = run_cli(fmt::format("render {} -q -o {}", scene.string(), out.string()), 120);
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(fs::exists(out));
}

// A camera placed beyond the world by its transform: every sample is a sample without a ray
// (transparent), and the load says so.
TEST(CrashFiles, ACameraMovedBeyondTheWorldGivesNoRaysAndSaysSo) {
  TempFolder dir;
  const fs::path scene =
      dir.write("far.toml", kHead +
                                "[camera]\nlook_from = [9e11, 0, 0]\nlook_at = [9e11, 0, -1]\n"
                                "transform = { translate = [9e11, 0, 0] }\n[[object]]\n"
                                "type = \"sphere\"\n");
  const fs::path out = dir.path() / "far.png";
  const CliResult r = run_cli(fmt::format("render {} -o {}", scene.string(), out.string()), 120);
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("gives no ray at any of 289 image positions"), std::string::npos) << r.out;
  const Image img = read_image(out, false);
  for (size_t i = 3; i < img.pixels.size(); i += 4) ASSERT_EQ(img.pixels[i], 0.f) << i;
}

// `--threads` beyond 1024 (the Python module faulted at 200,000; the CLI's own cap was a second
// copy of the number): one check, math/parallel.h.
TEST(CrashFiles, ThreadCountsOutOfRangeAreRefused) {
  TempFolder dir;
  const fs::path scene = dir.write("t.toml", kHead + "[[object]]\ntype = \"sphere\"\n");
  for (const char* n : {"200000", "-1", "1025"}) {
    const CliResult r = run_cli(fmt::format("render {} -q --threads {} -o {}", scene.string(), n,
                                            (dir.path() / "t.png").string()),
                                60);
    EXPECT_EQ(r.code, 2) << n << ": " << r.out;
    EXPECT_NE(r.out.find("0 (all cores) to 1024"), std::string::npos) << n << ": " << r.out;
  }
  const CliResult ok = run_cli(fmt::format("render {} -q --threads 0 -o {}", scene.string(),
                                           (dir.path() / "t.png").string()),
                               60);
  EXPECT_EQ(ok.code, 0) << ok.out;
}

// The editor: one edit with a camera at 2e18 aborted the server (its preview thread handed
// Embree the rays), losing every unsaved edit; JSON 20,000 levels deep overflowed a request
// thread's stack. Both are 400 now, and the server previews the next edit.
TEST_F(ServerTest, EditsThatCrashedTheServerAre400AndItGoesOn) {
  const int64_t v = version();
  const Reply far = edit("camera.look_from", json::array({2e18, 1, 4}), v);
  EXPECT_EQ(far.status, 400) << far.body;
  EXPECT_EQ(body_of(far).value("key", ""), "camera.look_from") << far.body;
  const std::string deep =
      "{\"version\": " + std::to_string(v) +
      ", \"edits\": [{\"key\": \"camera.fov\", \"value\": " + std::string(20000, '[') +
      std::string(20000, ']') + "}]}";
  const Reply nested = post("/api/edit", deep);
  EXPECT_EQ(nested.status, 400) << nested.body.substr(0, 300);
  EXPECT_NE(nested.body.find("nested more than 64 levels"), std::string::npos)
      << nested.body.substr(0, 300);
  const Reply fine = edit("camera.fov", 40, v);
  EXPECT_EQ(fine.status, 200) << fine.body;
  EXPECT_EQ(version(), v + 1);
}

}  // namespace
}  // namespace anamorph::test
