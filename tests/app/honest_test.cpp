// The second probe's "honest numbers and messages" (issue 32, docs/robustness.md, "Second probe:
// honest numbers and messages"), through the command line as a user meets them: messages that
// echo user text escape its control characters, file names with a NUL are refused, animation
// errors name their [[animate]] entry and frame before any frame is written, --resume refuses
// options it would ignore, and no command prints nan or inf.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "cli_util.h"
#include "io/image_io.h"
#include "test_util.h"

namespace anamorph {
namespace {

namespace fs = std::filesystem;

using Result = test::CliResult;
Result run(const std::string& args) { return test::run_cli(args, 120); }

struct Scratch {
  fs::path dir = fs::temp_directory_path() / ("anamorph_honest_" + std::to_string(getpid()));
  Scratch() { fs::create_directories(dir); }
  ~Scratch() { fs::remove_all(dir); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(dir / name, std::ios::binary) << text;
    return (dir / name).string();
  }
  std::string path(const std::string& name) const { return (dir / name).string(); }
};

bool has_control_bytes(const std::string& s) {
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if ((u < 0x20 && u != '\n') || u == 0x7f) return true;
  }
  return false;
}

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

// ---- control characters in messages --------------------------------------------------------

TEST(HonestMessages, ControlCharactersInKeysValuesAndArgumentsAreEscaped) {
  Scratch s;
  const std::string scene = s.write("esc.toml", "[camera]\n\"fov\\u001b[31m\" = 3\n");
  // A key in the file, a key and a value from --set, an unknown option, a material name.
  const Result key = run("info '" + scene + "'");
  EXPECT_EQ(key.code, 2) << key.out;
  EXPECT_TRUE(contains(key.out, "camera.fov\\x1b[31m: unknown key")) << key.out;
  // (Inside single quotes the shell passes every byte as it is.)
  const Result set = run("info '" + scene + "' --set 'camera.\x1b[2Jx=1'");
  const Result value = run("info '" + s.write("v.toml", "[[object]]\ntype = \"sphere\"\n") +
                           "' --set 'object.0.material=\"a\x9b\x07\"'");
  EXPECT_TRUE(contains(value.out, "--set: object[0].material: no material named")) << value.out;
  EXPECT_TRUE(contains(value.out, "a\\x9b\\x07")) << value.out;
  const Result option = run("info '" + scene + "' '--bogus\x1b[31m'");
  EXPECT_TRUE(contains(option.out, "--bogus\\x1b[31m")) << option.out;
  for (const Result* r : {&key, &set, &value, &option}) {
    EXPECT_EQ(r->code, 2) << r->out;
    EXPECT_FALSE(has_control_bytes(r->out)) << r->out;
  }
}

// ---- [[animate]] errors ------------------------------------------------------------------------

std::string frame_files(const Scratch& s) {
  std::string names;
  for (const auto& e : fs::directory_iterator(s.dir))
    if (e.path().extension() == ".png") names += e.path().filename().string() + " ";
  return names;
}

TEST(HonestMessages, AnimateErrorsNameTheEntryAndFrameBeforeAnyFrameIsWritten) {
  Scratch s;
  const std::string head = "[image]\nwidth = 8\nheight = 6\n[[object]]\ntype = \"sphere\"\n";
  // The view only (frames share one world), and an object (each frame a whole scene, with a
  // mesh that the check does not load).
  const std::string view = s.write(
      "view.toml", head + "[[animate]]\nkey = \"camera.fov\"\nkeys = [[0, 60], [10, 300]]\n");
  const std::string world = s.write(
      "world.toml", head + "[[object]]\ntype = \"mesh\"\nfile = \"" +
                        (test::data_dir() / "models" / "textured_quad.obj").string() +
                        "\"\n[[animate]]\nkey = \"object.0.radius\"\nkeys = [[0, 1], [4, -1]]\n");
  const struct {
    std::string scene, frames, want;
  } cases[] = {
      {view, "0:9",
       "view.toml:7:7: camera.fov: value 180 is out of range (must be (0, 180)) (at frame 5, the "
       "value of this [[animate]] entry)"},
      {world, "0:3",
       "world.toml:10:7: object[0].radius: value 0 is out of range (must be (0, 1e+12]) (at frame "
       "2, the value of this [[animate]] entry)"},
  };
  for (const auto& c : cases) {
    const Result r = run("render '" + c.scene + "' --frames " + c.frames + " -o '" +
                         s.path("f_%02d.png") + "' -q");
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_TRUE(contains(r.out, c.want)) << "got: " << r.out << "wanted: " << c.want;
    EXPECT_EQ(frame_files(s), "") << "frames were written before the error";
  }
  // The frames before the bad one render when asked for alone; a --set of the key wins over
  // the entry and is reported as such; a single frame names its frame too.
  EXPECT_EQ(run("render '" + view + "' --frames 0:4 -o '" + s.path("f_%02d.png") + "' -q").code, 0);
  const Result set =
      run("render '" + view + "' -o '" + s.path("x.png") + "' --set camera.fov=200 -q");
  EXPECT_TRUE(contains(set.out, "--set: camera.fov: value 200 is out of range")) << set.out;
  EXPECT_FALSE(contains(set.out, "[[animate]]")) << set.out;
}

// ---- --resume with other options --------------------------------------------------------------

std::string bytes_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(HonestMessages, ResumeRefusesOptionsThatWouldChangeTheRenderAndHonoursTheRest) {
  Scratch s;
  // A path-traced render that a time limit stops, leaving a checkpoint (noise that never falls
  // below the threshold: it cannot finish first). The camera stands outside the sphere: from
  // the default place, inside it, every pixel was black, so noise-free, and a machine fast
  // enough to finish two passes in the 10 ms finished the render and left no checkpoint.
  const std::string scene = s.write(
      "r.toml",
      "[image]\nwidth = 64\nheight = 48\n[camera]\nlook_from = [0, 1, 6]\nlook_at = [0, 0, 0]\n"
      "[render]\nintegrator = \"path\"\nantialias = \"pixel\"\n"
      "min_spp = 1\n"
      "max_spp = 1048576\nnoise_threshold = 1e-9\ntime_limit = 0.01\n[[object]]\ntype = "
      "\"sphere\"\n[[object]]\ntype = \"plane\"\npoint = [0, -1, 0]\n[[light]]\ntype = "
      "\"sphere\"\ncenter = [2, 2, 2]\n");  // (an area light: every pixel stays noisy)
  const std::string ck = s.path("r.ckpt"), out = s.path("r.png");
  const Result first = run("render '" + scene + "' -o '" + out + "' --checkpoint '" + ck + "'");
  ASSERT_EQ(first.code, 0) << first.out;
  ASSERT_TRUE(fs::exists(ck)) << first.out;
  const std::string checkpoint = bytes_of(ck);
  const struct {
    std::string options, named;
  } refused[] = {
      {"-o '" + s.path("other.png") + "'", "so -o would be ignored"},
      {"--width 16 --spp 4", "so --width, --spp would be ignored"},
      {"--set render.seed=3 --aov albedo", "so --set, --aov would be ignored"},
      {"--stats '" + s.path("st.json") + "'", "so --stats would be ignored"},
      {"--frames 0:1", "so --frames would be ignored"},
  };
  for (const auto& c : refused) {
    const Result r = run("render --resume '" + ck + "' " + c.options);
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_TRUE(contains(r.out,
                         "error: --resume continues the render exactly as the checkpoint's "
                         "command started it, " +
                             c.named))
        << r.out;
    EXPECT_TRUE(contains(r.out, "only --threads, --quiet, --checkpoint-every, --skip-existing"))
        << r.out;
    EXPECT_EQ(bytes_of(ck), checkpoint) << "the checkpoint changed: " << c.options;
  }
  EXPECT_FALSE(fs::exists(s.path("other.png")));
  EXPECT_FALSE(fs::exists(s.path("st.json")));
  // Honoured: --quiet silences the resumed run (which says where it resumed from otherwise),
  // --threads and --checkpoint-every are taken.
  const Result loud = run("render --resume '" + ck + "' --threads 1");
  EXPECT_EQ(loud.code, 0) << loud.out;
  EXPECT_TRUE(contains(loud.out, "resumed from")) << loud.out;
  if (fs::exists(ck)) {
    const Result quiet = run("render --resume '" + ck + "' -q --checkpoint-every 5m --threads 2");
    EXPECT_EQ(quiet.code, 0) << quiet.out;
    EXPECT_EQ(quiet.out, "");
  }
  const Result help = run("render --help");
  EXPECT_TRUE(contains(help.out,
                       "only --threads, --quiet, --checkpoint-every, --skip-existing "
                       "may be given with it"))
      << help.out;
}

// ---- form factors ----------------------------------------------------------------------------

bool prints_a_non_number(const std::string& out) {
  for (const char* w : {"nan", "inf", "NaN", "Inf"})
    if (contains(out, w)) return true;
  return false;
}

TEST(HonestNumbers, FormFactorsOfDegenerateScenesAreErrorsOrSayWhy) {
  Scratch s;
  const auto scene = [&](const std::string& name, const std::string& lamp_radius,
                         const std::string& emission, const std::string& wall) {
    // (A wall of reflectance 1 goes with a lamp of reflectance 1: nothing absorbs.)
    return s.write(
        name, "[[material]]\nname = \"lamp\"\ncolor = " + std::string(wall == "1" ? "1" : "0.5") +
                  "\nemission = " + emission + "\n[[material]]\nname = \"wall\"\ncolor = " + wall +
                  "\n[[object]]\ntype = \"sphere\"\nname = \"lamp\"\nradius = " + lamp_radius +
                  "\nmaterial = \"lamp\"\n[[object]]\ntype = \"sphere\"\nname = "
                  "\"dome\"\nradius = 2\nmaterial = \"wall\"\n");
  };
  const std::string args = " --inward dome --samples 64 --rays 64";
  const struct {
    std::string command, want;
    int code;
  } cases[] = {
      {"formfactors '" + scene("zero.toml", "0", "1", "0.6") + "'" + args,
       "zero.toml:11:10: object[0].radius: value 0 is out of range (must be (0, 1e+12])", 2},
      {"formfactors '" + scene("tiny.toml", "1e-200", "1", "0.6") + "'" + args,
       "lamp: no row (its surface area underflows to 0 (too small for double precision)); a "
       "receiver only",
       0},
      {"formfactors '" + scene("tiny.toml", "1e-200", "1", "0.6") + "'" + args + " --radiosity",
       "error: radiosity needs a row of form factors for every object, and 'lamp' can have none",
       2},
      {"formfactors '" + scene("small.toml", "1e-100", "1", "0.6") + "'" + args + " --radiosity",
       "lamp                     B/pi (1.00000, 1.00000, 1.00000)  path (1.00000, 1.00000, "
       "1.00000)",
       0},
      {"formfactors '" + scene("bright.toml", "0.5", "1e308", "0.6") + "'" + args + " --radiosity",
       "bright.toml:4:12: material[0].emission: value 1e+308 is out of range (must be [0, 1e+38])",
       2},
      {"formfactors '" + scene("rho.toml", "0.5", "1", "5") + "'" + args + " --radiosity",
       "rho.toml:7:9: material[1].color: value 5 is out of range (must be [0, 1])", 2},
      {"formfactors '" + scene("lossless.toml", "0.5", "1", "1") + "'" + args + " --radiosity",
       "the radiosity system (I - rho F) B = E has no solution in the red channel", 2},
  };
  for (const auto& c : cases) {
    const Result r = run(c.command);
    EXPECT_EQ(r.code, c.code) << c.command << "\n" << r.out;
    EXPECT_TRUE(contains(r.out, c.want)) << "got: " << r.out << "wanted: " << c.want;
    EXPECT_FALSE(prints_a_non_number(r.out)) << r.out;
  }
}

TEST(HonestNumbers, FormFactorCsvQuotesNamesAndTheEnvironmentRowIsNotAnObject) {
  Scratch s;
  // Names with a comma, a quote, a line break, and one named like the environment column.
  const std::string names[] = {"a,b", "say \\\"hi\\\"", "two\\nlines", "environment"};
  std::string toml;
  for (int i = 0; i < 4; ++i)
    toml += "[[object]]\ntype = \"sphere\"\nradius = 0.2\nname = \"" + names[i] +
            "\"\ntransform = { translate = [" + std::to_string(i) + ", 0, 0] }\n";
  const std::string scene = s.write("names.toml", toml), csv = s.path("f.csv");
  const Result r = run("formfactors '" + scene + "' --samples 8 --rays 16 -o '" + csv + "'");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(contains(r.out,
                       "warning: the object named 'environment' is listed as "
                       "'environment#2'"))
      << r.out;
  EXPECT_TRUE(contains(r.out, "  two\\nlines (area")) << "the table escapes names: " << r.out;
  // Python's csv module, an independent reader, sees each row's five fields and the names.
  const Result read = test::run_shell(
      "python3 -c 'import csv,sys,json; rows=list(csv.reader(open(sys.argv[1], newline=\"\")));"
      "assert all(len(x)==5 for x in rows), rows; print(json.dumps(sorted({x[0] for x in "
      "rows[1:]})), json.dumps(sorted({x[1] for x in rows[1:]})))' '" +
      csv + "'");
  EXPECT_EQ(read.code, 0) << read.out;
  EXPECT_EQ(read.out,
            "[\"a,b\", \"environment#2\", \"say \\\"hi\\\"\", \"two\\nlines\"] [\"a,b\", "
            "\"environment\", \"environment#2\", \"say \\\"hi\\\"\", \"two\\nlines\"]\n");
  // The JSON, read by Python's json module: the same names, the environment last among columns.
  const std::string json = s.path("f.json");
  ASSERT_EQ(run("formfactors '" + scene + "' --samples 8 --rays 16 -o '" + json + "'").code, 0);
  const Result columns = test::run_shell(
      "python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))[\"columns\"])' '" + json +
      "'");
  EXPECT_EQ(columns.out, "['a,b', 'say \"hi\"', 'two\\nlines', 'environment#2', 'environment']\n");
}

// ---- compare ---------------------------------------------------------------------------------

TEST(HonestNumbers, CompareRefusesImagesWithInfOrNaNInsteadOfPrintingThem) {
  Scratch s;
  OutputImage img;
  img.width = 3, img.height = 2;
  img.layers.push_back({"", {"R", "G", "B", "A"}, std::vector<float>(24, 0.25f)});
  const std::string fine = s.path("fine.exr"), bad = s.path("bad.exr");
  write_exr(fine, img);
  img.layers[0].data[4 * 4 + 1] = std::numeric_limits<float>::infinity();  // pixel (1, 1) G
  img.layers[0].data[4 * 5 + 2] = std::numeric_limits<float>::quiet_NaN();
  write_exr(bad, img);
  const Result ok = run("compare '" + fine + "' '" + fine + "'");
  EXPECT_EQ(ok.code, 0) << ok.out;
  EXPECT_TRUE(contains(ok.out, "rmse 0\n")) << ok.out;
  for (const std::string& args : {"'" + bad + "' '" + fine + "'", "'" + fine + "' '" + bad + "'"}) {
    const Result r = run("compare " + args);
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_TRUE(contains(r.out,
                         "bad.exr: 2 colour values are not finite numbers, the first at "
                         "pixel (1, 1) channel G: inf"))
        << r.out;
    EXPECT_FALSE(contains(r.out, "rmse")) << r.out;
  }
}

// ---- integers too large for 64 bits -------------------------------------------------------------

TEST(HonestMessages, IntegersBeyondSixtyFourBitsAreOutOfTheKeysRange) {
  Scratch s;
  const std::string scene = s.write("s.toml", "[image]\nwidth = 4\nheight = 4\n");
  const std::string as_number = s.write("n.toml", "[image]\nwidth = 1e30\n");
  const struct {
    std::string args, want;
  } cases[] = {
      {"info '" + scene + "' --set image.width=1180591620717411303424",
       "--set: image.width: value 1.1805916207174113e+21 is out of range (must be [1, 65536])"},
      {"info '" + scene + "' --set render.seed=-1_000_000_000_000_000_000_000",
       "render.seed: value -1e+21 is out of range"},
      {"info '" + as_number + "'", "n.toml:2:9: image.width: value 1e+30 is out of range"},
      {"info '" + scene + "' --set render.seed=1e16",
       "render.seed: value 1e+16 is out of range (must be an integer;"},
      // (Text TOML rejects for another reason stays a string.)
      {"info '" + scene + "' --set image.width=1__2",
       "image.width: expected an integer, got a string"},
      {"info '" + scene + "' --set image.width=00000000000000000000001",
       "image.width: expected an integer, got a string"},
  };
  for (const auto& c : cases) {
    const Result r = run(c.args);
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_TRUE(contains(r.out, c.want)) << "got: " << r.out << "wanted: " << c.want;
  }
}

// ---- scattered points far outside the image ---------------------------------------------------

TEST(HonestMessages, AScatteredPointAtUOf1e300IsOutOfRangeNotCollinear) {
  Scratch s;
  const std::string scene = s.write(
      "sc.toml",
      "[camera.org]\ntype = \"scattered\"\npoints = [[0, 0, -1, 1, 0], [1, 0, 1, 1, 0], [0, 1, -1, "
      "-1, 0], [1, 1, 1, -1, 0.1], [1e300, 0.5, 0, 0, 0.5]]\n[camera.dir]\ntype = \"constant\"\n");
  const Result r = run("info '" + scene + "'");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_TRUE(contains(r.out,
                       "sc.toml:3:10: camera.org.points: point 4: u = 1e+300 is out of "
                       "range (must be within [-1e+06, 1e+06]"))
      << r.out;
  EXPECT_FALSE(contains(r.out, "line")) << r.out;
}

// ---- NUL in file names ------------------------------------------------------------------------

TEST(HonestMessages, NulInAFileNameIsRefusedWhereverAPathEnters) {
  Scratch s;
  const std::string tex = s.path("tex.png");
  // The file the cut names would reach exists: each use must still be an error.
  ASSERT_EQ(run("render '" + s.write("t.toml", "[image]\nwidth = 4\nheight = 4\n") + "' -o '" +
                tex + "' -q")
                .code,
            0);
  const std::string sphere = "[image]\nwidth = 4\nheight = 4\n[[object]]\ntype = \"sphere\"\n";
  const std::string texture =
      s.write("texture.toml", sphere +
                                  "material = \"m\"\n[[material]]\nname = \"m\"\ncolor = { type = "
                                  "\"image\", file = \"tex.png\\u0000x\" }\n");
  const std::string mesh =
      s.write("mesh.toml", "[[object]]\ntype = \"mesh\"\nfile = \"tex.png\\u0000.gltf\"\n");
  const std::string include = s.write("include.toml", "include = \"t.toml\\u0000x\"\n");
  const std::string plain = s.write("plain.toml", sphere);
  const struct {
    std::string args, where;
  } cases[] = {
      {"render '" + texture + "' -o '" + s.path("o.png") + "'", "material[0].color.file"},
      {"info '" + mesh + "'", "object[0].file"},
      {"info '" + include + "'", "include"},
      {"render '" + plain + "' -o '" + s.path("o.png") +
           "' --set 'environment.file=\"tex.png\\u0000.hdr\"'",
       "--set: environment.file"},
      {"info '" + plain +
           "' --set 'camera.org={type=\"table\", file=\"tex.png\\u0000.exr\"}' --set "
           "'camera.dir={type=\"constant\"}'",
       "camera.org.file"},
  };
  for (const auto& c : cases) {
    const Result r = run(c.args);
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.out;
    EXPECT_TRUE(contains(r.out, c.where)) << r.out;
    EXPECT_TRUE(contains(r.out, "contains a NUL character (the system would read it as '"))
        << r.out;
    EXPECT_FALSE(fs::exists(s.path("o.png"))) << c.args;
  }
}

}  // namespace
}  // namespace anamorph
