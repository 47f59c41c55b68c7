// The command line as a user meets it: exit codes, messages, no half-written output files.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "cli_util.h"
#include "io/image_io.h"
#include "test_util.h"

namespace anamorph {

namespace fs = std::filesystem;

namespace {

using Result = test::CliResult;
Result run(const std::string& args) { return test::run_cli(args); }

fs::path temp_dir(const std::string& name) {
  const fs::path d =
      fs::temp_directory_path() / ("anamorph_cli_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string write(const fs::path& p, const std::string& text) {
  std::ofstream(p) << text;
  return p.string();
}

const char* kSmall =
    "[image]\nwidth = 24\nheight = 16\n[camera]\nlook_from = [0, 1, 4]\nlook_at = [0, 0, 0]\n"
    "[[object]]\ntype = \"sphere\"\n[[light]]\ntype = \"point\"\nposition = [2, 3, 2]\nintensity = "
    "10\n";

}  // namespace

TEST(Cli, VersionAndHelp) {
  const Result v = run("--version");
  EXPECT_EQ(v.code, 0);
  EXPECT_CONTAINS(v.out, "anamorph " ANAMORPH_VERSION);
  for (const char* cmd : {"render", "info", "rays", "project"}) {
    const Result h = run(std::string(cmd) + " --help");
    EXPECT_EQ(h.code, 0) << cmd;
    EXPECT_CONTAINS(h.out, "--set");
  }
  EXPECT_EQ(run("").code, 2);
  EXPECT_EQ(run("render").code, 2) << "missing scene argument";
}

TEST(Cli, RendersPngWithMetadata) {
  const fs::path d = temp_dir("png");
  const std::string scene = write(d / "s.toml", kSmall);
  const fs::path out = d / "out.png";
  const Result r = run("render " + scene + " -o " + out.string() + " --set camera.fov=70");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_CONTAINS(r.out, "Mrays/s");
  const auto meta = read_metadata(out);
  ASSERT_TRUE(meta.count("anamorph.command"));
  EXPECT_CONTAINS(meta.at("anamorph.command"), "camera.fov=70");
  EXPECT_CONTAINS(meta.at("anamorph.camera"), "perspective");
  const Image im = read_image(out);
  EXPECT_EQ(im.width, 24);
  EXPECT_EQ(im.height, 16);
  fs::remove_all(d);
}

TEST(Cli, AovsGoToOneExr) {
  const fs::path d = temp_dir("aov");
  const std::string scene = write(d / "s.toml", kSmall);
  const Result r =
      run("render " + scene + " -o " + (d / "o.exr").string() + " --aov albedo,normal,depth -q");
  ASSERT_EQ(r.code, 0) << r.out;
  int w, h;
  const auto ch = read_exr_channels(d / "o.exr", &w, &h);
  for (const char* c : {"R", "G", "B", "A", "albedo.R", "normal.X", "depth.Z"})
    EXPECT_TRUE(ch.count(c)) << c;
  EXPECT_EQ(run("render " + scene + " -o " + (d / "o.exr").string() + " --aov albedo,bogus").code,
            2);
  fs::remove_all(d);
}

TEST(Cli, BadSceneExitCode2WithLocationAndNoOutput) {
  const fs::path d = temp_dir("bad");
  const fs::path out = d / "out.png";
  struct Case {
    std::string text, expect;
  };
  const Case cases[] = {
      {"[image]\nwidth = 10\nhieght = 5\n",
       "s.toml:3:1: image.hieght: unknown key (did you mean 'height'?)"},
      {"[camera\n", "TOML syntax error"},
      {"[camera]\nfov = 200\n", "camera.fov"},
      {"[camera]\nfov = -1\n", "out of range"},
      {"[camera]\nfov = nan\n", "finite"},
      {"[[object]]\ntype = \"sphere\"\nradius = -2\n", "object[0].radius"},
      {"[[object]]\ntype = \"mesh\"\nfile = \"missing.obj\"\n", "file not found"},
      {"[render]\nspp = \"many\"\n", "expected an integer"},
  };
  for (const Case& c : cases) {
    const std::string scene = write(d / "s.toml", c.text);
    const Result r = run("render " + scene + " -o " + out.string());
    EXPECT_EQ(r.code, 2) << c.text << "\n" << r.out;
    EXPECT_CONTAINS(r.out, c.expect);
    EXPECT_FALSE(fs::exists(out)) << "no output for a bad scene";
  }
  EXPECT_EQ(run("render " + (d / "nope.toml").string()).code, 2);
  // An output no sink writes: the one message, naming the extension and every supported one.
  const Result jpg = run("render " + write(d / "s.toml", kSmall) + " -o " + (d / "x.jpg").string());
  EXPECT_EQ(jpg.code, 2) << jpg.out;
  EXPECT_CONTAINS(jpg.out, "unsupported extension '.jpg' (supported: .png, .exr)");
  fs::remove_all(d);
}

TEST(Cli, KilledRenderLeavesTheOldFileIntact) {
  const fs::path d = temp_dir("kill");
  const std::string scene = write(d / "s.toml", kSmall);
  const fs::path out = d / "out.png";
  ASSERT_EQ(run("render " + scene + " -q -o " + out.string()).code, 0);
  const std::string before = test::read_text(out);
  // A render that takes far longer than we wait, then SIGKILL (no chance to clean up).
  const pid_t pid = fork();
  if (pid == 0) {
    const std::string bin = test::binary().string();
    execl(bin.c_str(), bin.c_str(), "render", scene.c_str(), "-q", "-o", out.c_str(), "--width",
          "2000", "--height", "2000", "--spp", "4096", static_cast<char*>(nullptr));
    _exit(127);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(700));
  kill(pid, SIGKILL);
  int status;
  waitpid(pid, &status, 0);
  EXPECT_TRUE(WIFSIGNALED(status)) << "the render finished before it was killed";
  EXPECT_EQ(test::read_text(out), before) << "the previous image must survive byte for byte";
  // SIGINT: the renderer stops, leaves the output alone, puts the image so far beside it and
  // exits 3 (interrupted).
  const pid_t pid2 = fork();
  if (pid2 == 0) {
    const std::string bin = test::binary().string();
    execl(bin.c_str(), bin.c_str(), "render", scene.c_str(), "-q", "-o", out.c_str(), "--width",
          "2000", "--height", "2000", "--spp", "4096", static_cast<char*>(nullptr));
    _exit(127);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(700));
  kill(pid2, SIGINT);
  waitpid(pid2, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 3);
  EXPECT_EQ(test::read_text(out), before);
  EXPECT_TRUE(fs::exists(d / "out.partial.png"));
  fs::remove_all(d);
}

TEST(Cli, InfoRaysProject) {
  const fs::path d = temp_dir("info");
  const std::string scene = write(d / "s.toml", kSmall);
  const Result info = run("info " + scene);
  ASSERT_EQ(info.code, 0) << info.out;
  EXPECT_CONTAINS(info.out, "shapes      1");
  EXPECT_CONTAINS(info.out, "perspective");
  const Result rays = run("rays " + scene + " --width 4 --height 3 -o " + (d / "r.csv").string());
  ASSERT_EQ(rays.code, 0) << rays.out;
  const std::string csv = test::read_text(d / "r.csv");
  EXPECT_EQ(csv.rfind("px,py,u,v,ox,oy,oz,dx,dy,dz,valid\n", 0), 0u);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 13);
  // The camera looks at the origin: it projects to the image center.
  const Result pr = run("project " + scene + " --point 0,0,0");
  ASSERT_EQ(pr.code, 0) << pr.out;
  EXPECT_CONTAINS(pr.out, "px 12.000000 py 8.000000");
  const Result json = run("project " + scene + " --point 0,0,0 --json");
  ASSERT_EQ(json.code, 0) << json.out;
  EXPECT_CONTAINS(json.out, "\"width\": 24, \"height\": 16, \"pixels\": [[12, 8]]");  // every digit
  EXPECT_EQ(run("project " + scene + " --point 1,2").code, 2);
  fs::remove_all(d);
}

TEST(Cli, RobustnessModels) {
  ANAMORPH_REQUIRE_SHARED();
  const fs::path d = temp_dir("robust");
  const fs::path gl = test::shared_scenes() / "gltf" / "robustness";
  const std::string bad =
      write(d / "inf.toml", std::string(kSmall) + "[[object]]\ntype = \"mesh\"\nfile = \"" +
                                (gl / "BoxWithInfinites.glb").string() + "\"\n");
  const Result r1 = run("render " + bad + " -o " + (d / "o.png").string());
  EXPECT_EQ(r1.code, 2) << r1.out;
  EXPECT_CONTAINS(r1.out, "non-finite");
  EXPECT_FALSE(fs::exists(d / "o.png"));
  const std::string fix =
      write(d / "bad_normals.toml", std::string(kSmall) + "[[object]]\ntype = \"mesh\"\nfile = \"" +
                                        (gl / "BoxBadNormals.glb").string() + "\"\n");
  const Result r2 = run("render " + fix + " -q -o " + (d / "o.png").string());
  EXPECT_EQ(r2.code, 0) << r2.out;
  EXPECT_CONTAINS(r2.out, "warning");
  fs::remove_all(d);
}

}  // namespace anamorph

namespace anamorph {

// The summary line names the sampling that happened, and which adaptive scheme: the AOV
// integrators take render.spp samples under an adaptive scheme too.
TEST(Cli, SummarySaysAdaptiveOnlyWhenSamplesVaried) {
  const fs::path d = temp_dir("summary");
  const std::string scene =
      write(d / "s.toml", std::string(kSmall) + "[render]\nantialias = \"adaptive\"\n");
  const Result w = run("render " + scene + " -o " + (d / "w.png").string());
  ASSERT_EQ(w.code, 0) << w.out;
  EXPECT_CONTAINS(w.out, "adaptive (lattice), ");  // (which scheme: whitted's adaptive)
  const Result p = run("render " + scene + " --integrator path --set render.max_spp=16 -o " +
                       (d / "p.png").string());
  ASSERT_EQ(p.code, 0) << p.out;
  EXPECT_CONTAINS(p.out, "adaptive (pixel), ");
  const Result a = run("render " + scene + " --integrator depth -o " + (d / "a.png").string());
  ASSERT_EQ(a.code, 0) << a.out;
  EXPECT_CONTAINS(a.out, "1 spp, depth");
  EXPECT_EQ(a.out.find("adaptive"), std::string::npos) << a.out;
  const Result i = run("info " + scene + " --set render.integrator=depth");
  ASSERT_EQ(i.code, 0) << i.out;
  EXPECT_CONTAINS(i.out, "1 spp");
  fs::remove_all(d);
}

// Frames of a sequence equal still renders with the frame's values set, pixel for pixel, both
// when the keys change only the view (the frames share one renderer: load_view) and when they
// move geometry (each frame loads the scene).
TEST(Cli, FramesEqualStillRendersWithTheirValues) {
  const fs::path d = temp_dir("frames_still");
  const std::string view_keys =
      "[[animate]]\nkey = \"camera.fov\"\nkeys = [[0, 40], [2, 70]]\n"
      "[[animate]]\nkey = \"camera.look_from\"\nkeys = [[0, [0, 1, 4]], [2, [1, 1, 4]]]\n"
      "[[animate]]\nkey = \"image.width\"\nkeys = [[0, 24], [2, 32]]\ninterpolation = \"step\"\n";
  const std::string object_key =
      "[[animate]]\nkey = \"object.0.center\"\nkeys = [[0, [0, 0, 0]], [2, [0.5, 0, 0]]]\n";
  // The values at frames 0, 1, 2 as --set arguments.
  const char* view_sets[3] = {
      "--set camera.fov=40 --set 'camera.look_from=[0,1,4]' --set image.width=24",
      "--set camera.fov=55 --set 'camera.look_from=[0.5,1,4]' --set image.width=24",
      "--set camera.fov=70 --set 'camera.look_from=[1,1,4]' --set image.width=32"};
  const char* object_sets[3] = {"--set 'object.0.center=[0,0,0]'",
                                "--set 'object.0.center=[0.25,0,0]'",
                                "--set 'object.0.center=[0.5,0,0]'"};
  const std::string still = write(d / "still.toml", kSmall);
  for (const bool with_object : {false, true}) {
    const std::string name = with_object ? "moving" : "view";
    const std::string scene = write(
        d / (name + ".toml"), std::string(kSmall) + view_keys + (with_object ? object_key : ""));
    const Result r =
        run("render " + scene + " -q --frames 0:2 -o " + (d / (name + "_%d.png")).string());
    ASSERT_EQ(r.code, 0) << r.out;
    for (int f = 0; f < 3; ++f) {
      const fs::path frame = d / (name + "_" + std::to_string(f) + ".png");
      const fs::path ref = d / (name + "_still_" + std::to_string(f) + ".png");
      const Result s = run("render " + still + " -q " + view_sets[f] + " " +
                           (with_object ? object_sets[f] : "") + " -o " + ref.string());
      ASSERT_EQ(s.code, 0) << s.out;
      const Image a = read_image(frame, false), b = read_image(ref, false);
      ASSERT_EQ(a.width, b.width) << name << " frame " << f;
      ASSERT_EQ(a.height, b.height) << name << " frame " << f;
      size_t differ = 0;
      for (size_t i = 0; i < a.pixels.size(); ++i) differ += a.pixels[i] != b.pixels[i];
      EXPECT_EQ(differ, 0u) << name << " frame " << f << ": values differing from the still";
    }
  }
  fs::remove_all(d);
}

TEST(Cli, FramesRenderASequenceAndVideoNeedsFfmpeg) {
  const fs::path d = temp_dir("frames");
  const std::string scene =
      write(d / "s.toml",
            std::string(kSmall) + "[[animate]]\nkey = \"camera.fov\"\nkeys = [[0, 40], [2, 70]]\n");
  const Result r = run("render " + scene + " -q --frames 0:2 -o " + (d / "f_%03d.png").string());
  ASSERT_EQ(r.code, 0) << r.out;
  for (const char* f : {"f_000.png", "f_001.png", "f_002.png"}) EXPECT_TRUE(fs::exists(d / f)) << f;
  EXPECT_NE(test::read_text(d / "f_000.png"), test::read_text(d / "f_002.png"))
      << "the animation changes the image";
  EXPECT_EQ(read_metadata(d / "f_001.png").at("anamorph.frame"), "1");
  EXPECT_EQ(run("render " + scene + " --frames 0:2 -o " + (d / "nopattern.png").string()).code, 2);
  EXPECT_EQ(run("render " + scene + " --frames 5:2 -o " + (d / "f_%03d.png").string()).code, 2);
  // Without ffmpeg on the PATH, --video says so before rendering anything.
  const Result v = run("render " + scene + " --frames 0:1 -o " + (d / "v_%03d.png").string() +
                       " --video " + (d / "v.mp4").string() + " 2>&1; true");
  if (std::system("command -v ffmpeg >/dev/null 2>&1") != 0) {
    EXPECT_CONTAINS(v.out, "not on the PATH");
    EXPECT_FALSE(fs::exists(d / "v_000.png"))
        << "nothing is rendered when the video cannot be made";
  } else {
    EXPECT_TRUE(fs::exists(d / "v.mp4")) << v.out;
    EXPECT_GT(fs::file_size(d / "v.mp4"), 0u);
  }
  fs::remove_all(d);
}

}  // namespace anamorph

namespace anamorph {

TEST(Cli, CoinsInInfoAndOverlay) {
  const fs::path d = temp_dir("coins");
  const std::string scene = write(
      d / "s.toml", std::string(kSmall) +
                        "[[camera.coin]]\nposition = [0, 0, 0]\nstrength = 0.5\nradius = 0.3\n");
  const Result info = run("info " + scene);
  ASSERT_EQ(info.code, 0) << info.out;
  // The coin sits where the camera looks: the image center.
  EXPECT_CONTAINS(info.out, "(uc, vc) = (0.5000, 0.5000)");
  const Result r = run("render " + scene + " -q -o " + (d / "o.png").string() + " --aov coins");
  ASSERT_EQ(r.code, 0) << r.out;
  ASSERT_TRUE(fs::exists(d / "o.coins.png"));
  int w, h;
  const auto ch = read_exr_channels(d / "o.exr", &w, &h);
  ASSERT_TRUE(ch.count("coins.A"));
  const auto& a = ch.at("coins.A");
  EXPECT_GT(a[size_t(h / 2) * w + w / 2], 0.5f) << "marker at the coin's image position";
  EXPECT_EQ(a[0], 0.0f) << "nothing in the corner";
  fs::remove_all(d);
}

}  // namespace anamorph

namespace anamorph {

TEST(Cli, FormFactorsWritesItsMatrixAndRefusesBadRequests) {
  const fs::path d = temp_dir("formfactors");
  const std::string scene = write(d / "discs.toml",
                                  "[[object]]\ntype = \"disk\"\nname = \"d1\"\nradius = 1\n"
                                  "[[object]]\ntype = \"disk\"\nname = \"d2\"\nradius = 0.6\n"
                                  "transform = { rotate = [180, 1, 0, 0], translate = [0, 0.8, "
                                  "0] }\n");
  const Result r = run("formfactors " + scene + " --samples 256 -o " + (d / "f.csv").string());
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_CONTAINS(r.out, "-> d2");
  EXPECT_CONTAINS(r.out, "reciprocity");
  const std::string csv = test::read_text(d / "f.csv");
  EXPECT_EQ(csv.rfind("from,to,area_from,F,stderr\nd1,d1,3.14159265", 0), 0u) << csv;
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 7) << "2 rows x 3 columns + header";
  const Result j = run("formfactors " + scene + " --samples 64 -o " + (d / "f.json").string());
  ASSERT_EQ(j.code, 0) << j.out;
  EXPECT_CONTAINS(test::read_text(d / "f.json"), "\"columns\": [\"d1\", \"d2\", \"environment\"]");
  const Result unknown = run("formfactors " + scene + " --objects d3");
  EXPECT_EQ(unknown.code, 2) << unknown.out;
  EXPECT_CONTAINS(unknown.out, "no object named 'd3' (the scene has: d1, d2)");
  EXPECT_EQ(run("formfactors " + scene + " -o f.txt").code, 2);
  const Result partial = run("formfactors " + scene + " --objects d1 --radiosity");
  EXPECT_EQ(partial.code, 2) << partial.out;
  EXPECT_CONTAINS(partial.out, "radiosity needs a row of form factors for every object");
  fs::remove_all(d);
}

}  // namespace anamorph

namespace anamorph {

// bench counts warm-up and measured frames with options of their own; its old --frames W M
// still works with a warning, and render's meaning of --frames (A:B) is an error saying which.
TEST(Cli, BenchWarmUpAndMeasure) {
  const fs::path d = temp_dir("bench");
  const std::string scene = write(d / "s.toml", kSmall);
  const auto frames = [](const std::string& out) {
    return std::count(out.begin(), out.end(), '\n') - 5;  // (the five BENCHMARK_ lines)
  };
  const Result r = run("bench " + scene + " --warm-up 1 --measure 2");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(frames(r.out), 3) << r.out;
  EXPECT_CONTAINS(r.out, "(warm-up)");
  const Result old = run("bench " + scene + " --frames 0 2");
  ASSERT_EQ(old.code, 0) << old.out;
  EXPECT_CONTAINS(old.out, "bench --frames 0 2 is deprecated: write --warm-up 0 --measure 2");
  EXPECT_EQ(frames(old.out), 3) << old.out;  // (and the warning line)
  const Result range = run("bench " + scene + " --frames 0:5");
  EXPECT_EQ(range.code, 2) << range.out;
  EXPECT_CONTAINS(range.out, "--frames A:B picks animation frames in `render` only");
  fs::remove_all(d);
}

}  // namespace anamorph
