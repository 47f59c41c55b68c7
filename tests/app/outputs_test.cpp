// No output of a run may overwrite a file the run reads, another output of the same run or a
// read-only file (app/output_guard.h): exit 2, a message naming both roles, the file untouched.
// Generated: every output option of every command that writes (the table below, checked against
// `anamorph --help`) against every file the scene reads (as `anamorph info` lists them), each
// output aimed at the input through a symbolic link (the files are compared by device and inode)
// and, where the names allow, by the input's own path. Then the probe's examples as written.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "cli_util.h"
#include "run_fixture.h"
#include "test_util.h"

namespace anamorph {
namespace {

namespace fs = std::filesystem;
using test::CliResult;

struct Input {
  std::string role;
  fs::path path;
};

// The files `anamorph info` says the scene reads ("reads N file(s)", then "  ROLE: PATH").
std::vector<Input> inputs_of(const std::string& scene) {
  const CliResult r = test::run_cli("info " + scene);
  EXPECT_EQ(r.code, 0) << r.out;
  std::vector<Input> in;
  const size_t at = r.out.find("\nreads ");
  if (at == std::string::npos) return in;
  std::istringstream lines(r.out.substr(at + 1));
  std::string line;
  std::getline(lines, line);
  while (std::getline(lines, line) && line.rfind("  ", 0) == 0) {
    const size_t colon = line.rfind(": /");
    if (colon != std::string::npos)
      in.push_back({line.substr(2, colon - 2), line.substr(colon + 2)});
  }
  return in;
}

// An output option and how to aim it: `file` is the name, in the case's folder {d}, of what the
// option writes; `args` the rest of the command line ({scene}, {d}); `named` how the error
// names the output.
struct OutputOption {
  const char* command;
  const char* file;
  const char* args;
  const char* named;
  bool in_folder = false;  // run in {d} (the default output, out/scene.png, is relative)
};

const OutputOption kOptions[] = {
    {"render", "out.png", "{scene} -o {d}/out.png", "-o "},
    {"render", "out.exr", "{scene} -o {d}/out.png --aov albedo", "the AOVs' EXR"},
    {"render", "out.coins.png", "{scene} -o {d}/out.png --aov coins", "the coin overlay"},
    {"render", "out.partial.png", "{scene} -o {d}/out.png", "the image so far"},
    {"render", "out.partial.exr", "{scene} -o {d}/out.png --aov depth", "the AOVs so far"},
    {"render", "stats.json", "{scene} -o {d}/out.png --stats {d}/stats.json", "--stats "},
    {"render", "r.ckpt", "{scene} -o {d}/out.png --checkpoint {d}/r.ckpt", "--checkpoint "},
    {"render", "f_0000.png", "{scene} --frames 0:0 -o {d}/f_%04d.png", "-o "},
    {"render", "s_0000.json", "{scene} --frames 0:0 -o {d}/f_%04d.png --stats {d}/s_%04d.json",
     "--stats "},
    {"render", "c_0000.ckpt", "{scene} --frames 0:0 -o {d}/f_%04d.png --checkpoint {d}/c_%04d.ckpt",
     "--checkpoint "},
    {"render", "v.mp4", "{scene} --frames 0:0 -o {d}/f_%04d.png --video {d}/v.mp4", "--video "},
    {"render", "out/scene.png", "{scene}", "the default output", true},
    {"rays", "rays.csv", "{scene} -o {d}/rays.csv", "-o "},
    {"rays", "r.exr", "{scene} -o {d}/r.exr", "-o "},
    {"formfactors", "ff.csv", "{scene} --samples 1 --rays 1 -o {d}/ff.csv", "-o "},
    {"formfactors", "ff.json", "{scene} --samples 1 --rays 1 -o {d}/ff.json", "-o "},
    {"schema", "schema.json", "-o {d}/schema.json", "-o "},
    {"stmap", "m.exr", "{scene} --source equirect -o {d}/m.exr", "-o "},
    // (The input image is not read before the outputs are checked: it need not exist.)
    {"warp", "w.png", "{scene} {d}/in.png --source fisheye:180 -o {d}/w.png", "-o "},
    {"calib", "c.yml", "{scene} --format opencv -o {d}/c.yml", "-o "},
    {"calib", "cameras.txt", "{scene} --format colmap -o {d}", "-o "},
    {"calib", "k.yaml", "{scene} --format kalibr -o {d}/k.yaml", "-o "},
    {"solve", "s.toml", "{scene} -o {d}/s.toml", "-o "},
};
// Commands that write no file of their own (stdout only), and serve, whose files are the
// editor's (its save replaces the scene it edits on purpose; tests/server hold it).
const std::set<std::string> kWriteNothing = {"info", "project", "bench", "compare", "serve"};
// The options by which a command names a file it writes.
const char* kOutputOptions[] = {"--output", "--stats", "--checkpoint", "--video"};

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size()))
    s.replace(at, from.size(), to);
  return s;
}

std::string command_line(const OutputOption& o, const fs::path& d, const std::string& scene) {
  const std::string cmd = std::string(o.command) + " " +
                          replace_all(replace_all(o.args, "{scene}", scene), "{d}", d.string());
  return o.in_folder ? "cd '" + d.string() + "' && " + test::binary().string() + " " + cmd
                     : test::binary().string() + " " + cmd;
}

struct Fixture {
  test::ScratchDir dir{"outputs"};
  std::string scene;
  std::vector<fs::path> files;
  Fixture() { scene = test::write_reading_scene(dir.dir, &files); }
};

// Runs `o` with its file (a fresh folder's `o.file`) made by `make`; expects a refusal naming the
// output and `expect`, and no temporary file anywhere.
void expect_refused(const OutputOption& o, const Fixture& fx, const fs::path& d,
                    const std::string& expect, const std::string& cmd) {
  const CliResult r = test::run_shell(cmd);
  EXPECT_EQ(r.code, 2) << cmd << "\n" << r.out;
  EXPECT_CONTAINS(r.out, "error: " + std::string(o.named));
  EXPECT_CONTAINS(r.out, expect);
  const auto left = test::temporaries_in(d), left_fx = test::temporaries_in(fx.dir.dir);
  EXPECT_TRUE(left.empty() && left_fx.empty())
      << cmd << ": " << left.size() + left_fx.size() << " temporary file(s) left";
}

}  // namespace

// The scene reads every kind of file, `info` lists them all with their roles, and the scene
// renders (so the refusals below are the outputs' doing).
TEST(Outputs, TheFixtureReadsEveryKindOfFileAndRenders) {
  Fixture fx;
  const std::vector<Input> in = inputs_of(fx.scene);
  const std::set<std::string> roles = {
      "the scene file",
      "a file the scene includes",
      "a ray table",
      "the environment map",
      "a texture",
      "a model",
      "a buffer of " + (fx.dir.dir / "tri.gltf").string(),
      "an image that " + (fx.dir.dir / "tri.gltf").string() + " uses",
      "a file that " + (fx.dir.dir / "tri.obj").string() + " uses"};
  std::set<std::string> seen;
  for (const Input& i : in) seen.insert(i.role);
  for (const std::string& r : roles) EXPECT_EQ(seen.count(r), 1u) << "no input with role " << r;
  std::vector<fs::path> paths;
  for (const Input& i : in) paths.push_back(fs::canonical(i.path));
  for (const fs::path& f : fx.files)
    EXPECT_NE(std::find(paths.begin(), paths.end(), fs::canonical(f)), paths.end())
        << f << " is read but not listed";
  const CliResult r = test::run_cli("render " + fx.scene + " -q -o " +
                                    (fx.dir.dir / "fine.png").string() + " --aov albedo,coins");
  EXPECT_EQ(r.code, 0) << r.out;
}

// Every command that writes is in the table, with every option that names an output.
TEST(Outputs, TheTableCoversEveryCommandAndOutputOption) {
  const CliResult help = test::run_cli("--help");
  const std::regex sub(R"(\n  ([a-z]+)\s)");
  std::set<std::string> commands;
  const size_t at = help.out.find("Subcommands:");
  ASSERT_NE(at, std::string::npos) << help.out;
  const std::string tail = help.out.substr(at);
  for (auto it = std::sregex_iterator(tail.begin(), tail.end(), sub); it != std::sregex_iterator();
       ++it)
    commands.insert((*it)[1]);
  ASSERT_GT(commands.size(), 5u) << help.out;
  for (const std::string& c : commands) {
    const bool in_table = std::any_of(std::begin(kOptions), std::end(kOptions),
                                      [&](const OutputOption& o) { return c == o.command; });
    EXPECT_TRUE(in_table || kWriteNothing.count(c)) << "command " << c << " is not classified";
    const std::string h = test::run_cli(c + " --help").out;
    for (const char* opt : kOutputOptions) {
      if (h.find(std::string(opt) + " ") == std::string::npos) continue;
      const std::string flag = std::string(opt) == "--output" ? "-o " : std::string(opt) + " ";
      const bool covered = std::any_of(std::begin(kOptions), std::end(kOptions), [&](auto& o) {
        return c == o.command && std::string(o.args).find(flag) != std::string::npos;
      });
      EXPECT_TRUE(covered) << c << " " << opt << " writes a file but is not in the table";
    }
  }
}

// Every output option against every input, through a symbolic link named as the option needs,
// and by the input's own path where its name fits the option.
TEST(Outputs, NoOutputOptionOverwritesAnyInput) {
  Fixture fx;
  const std::vector<Input> inputs = inputs_of(fx.scene);
  ASSERT_GE(inputs.size(), 8u);
  // Under the sanitizers (each run about 10x slower) a third of the pairs, chosen so that every
  // option still meets several inputs and every input several options.
  const size_t stride = test::kSanitized ? 3 : 1;
  int runs = 0;
  for (size_t oi = 0; oi < std::size(kOptions); ++oi) {
    const OutputOption& o = kOptions[oi];
    if (std::string(o.command) == "schema") continue;  // (it reads no file)
    for (size_t ii = 0; ii < inputs.size(); ++ii) {
      if ((oi + ii) % stride != 0) continue;
      const Input& in = inputs[ii];
      const std::string before = test::read_text(in.path);
      const test::ScratchDir d("outputs_case");
      fs::create_directories((d.dir / o.file).parent_path());
      fs::create_symlink(fs::absolute(in.path), d.dir / o.file);
      expect_refused(o, fx, d.dir, in.role + " this run reads", command_line(o, d.dir, fx.scene));
      ++runs;
      // The input's own path where the option takes a name of that kind.
      const std::string direct = "{d}/" + std::string(o.file);
      if (in.path.extension() == fs::path(o.file).extension() &&
          std::string(o.args).find(direct) != std::string::npos) {
        OutputOption byname = o;
        const std::string args = replace_all(o.args, direct, in.path.string());
        byname.args = args.c_str();
        expect_refused(o, fx, d.dir, in.role + " this run reads",
                       command_line(byname, d.dir, fx.scene));
        ++runs;
      }
      EXPECT_EQ(test::read_text(in.path), before) << in.path << " was changed by " << o.args;
      EXPECT_TRUE(fs::is_symlink(d.dir / o.file)) << o.file << " was replaced";
    }
  }
  EXPECT_GE(runs, 16 * 8 / int(stride));
}

// Every output option against a read-only file (mode 0444; rename(2) would replace it, and root
// may write anything): refused, the file unchanged.
TEST(Outputs, NoOutputOptionReplacesAReadOnlyFile) {
  Fixture fx;
  for (const OutputOption& o : kOptions) {
    const test::ScratchDir d("outputs_ro");
    const fs::path target = d.dir / o.file;
    fs::create_directories(target.parent_path());
    std::ofstream(target) << "keep me";
    fs::permissions(target, fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
    expect_refused(o, fx, d.dir, "is read-only (mode 0444)", command_line(o, d.dir, fx.scene));
    EXPECT_EQ(test::read_text(target), "keep me") << o.args;
  }
}

// Two outputs of one run on one file: each option that names its file freely (--stats,
// --checkpoint) against every other output of the same render.
TEST(Outputs, NoTwoOutputsOfARunShareAFile) {
  Fixture fx;
  const test::ScratchDir d("outputs_pair");
  const std::string base = "render " + fx.scene + " -o " + (d.dir / "out.png").string();
  const std::vector<std::pair<std::string, std::string>> others = {
      {"--aov albedo", "out.png"},
      {"--aov albedo", "out.exr"},
      {"--aov albedo", "out.partial.png"},
      {"--aov albedo", "out.partial.exr"},
      {"--aov coins", "out.coins.png"},
      {"--stats " + (d.dir / "x.json").string(), "x.json"},
      {"--checkpoint " + (d.dir / "x.ckpt").string(), "x.ckpt"}};
  for (const char* free : {"--stats", "--checkpoint"})
    for (const auto& [extra, file] : others) {
      if (extra.rfind(free, 0) == 0) continue;
      const std::string cmd = base + " " + extra + " " + free + " " + (d.dir / file).string();
      const CliResult r = test::run_cli(cmd);
      EXPECT_EQ(r.code, 2) << cmd << "\n" << r.out;
      EXPECT_CONTAINS(r.out, "two outputs of one run cannot share a file");
      EXPECT_FALSE(fs::exists(d.dir / file)) << cmd;
    }
}

// ---- the probe's examples, as written --------------------------------------------------------

// `anamorph render scene.png`, a TOML file named .png and no -o: the default output is
// out/scene.png, never the scene.
TEST(Outputs, ATomlNamedPngWithoutOutputKeepsTheScene) {
  const test::ScratchDir d("outputs_png_scene");
  const std::string text = "[image]\nwidth = 8\nheight = 8\n[[object]]\ntype = \"sphere\"\n";
  d.write("scene.png", text);
  const CliResult r = test::run_shell("cd '" + d.dir.string() + "' && " + test::binary().string() +
                                      " render scene.png");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(test::read_text(d.dir / "scene.png"), text);
  EXPECT_EQ(test::read_text(d.dir / "out/scene.png").substr(1, 3), "PNG");
  EXPECT_CONTAINS(r.out, "out/scene.png: 8x8");  // (the summary says where)
}

TEST(Outputs, TheProbesExamplesAreRefused) {
  Fixture fx;
  const test::ScratchDir d("outputs_examples");
  const std::string text = "[image]\nwidth = 8\nheight = 8\n[[object]]\ntype = \"sphere\"\n";
  const std::string exr_scene = d.write("scene.exr", text), out_exr = d.write("out.exr", text),
                    toml = d.write("s.toml", text);
  const fs::path png = d.dir / "out.png";
  struct Case {
    std::string args, message;
    fs::path kept;
  };
  const Case cases[] = {
      {"render " + exr_scene + " -o " + exr_scene,
       "-o " + exr_scene + " is the scene file this run reads", exr_scene},
      {"render " + out_exr + " -o " + png.string() + " --aov albedo",
       "the AOVs' EXR " + out_exr + " (written beside -o " + png.string() +
           ") is the scene file this run reads",
       out_exr},
      {"render " + toml + " -o " + png.string() + " --stats " + toml,
       "--stats " + toml + " is the scene file this run reads", toml},
      {"render " + fx.scene + " -o " + (fx.dir.dir / "tex.png").string(),
       "is a texture this run reads", fx.dir.dir / "tex.png"},
      {"render " + fx.scene + " -o " + (fx.dir.dir / "env.png").string(),
       "is the environment map this run reads", fx.dir.dir / "env.png"},
      {"rays " + fx.scene + " -o " + (fx.dir.dir / "rays.exr").string(),
       "is a ray table this run reads", fx.dir.dir / "rays.exr"},
      {"render " + toml + " --stats " + png.string() + " -o " + png.string(),
       "--stats " + png.string() + " is also -o " + png.string(), png},
  };
  for (const Case& c : cases) {
    const std::string before = test::read_text(c.kept);
    const CliResult r = test::run_cli(c.args);
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.out;
    EXPECT_CONTAINS(r.out, c.message);
    EXPECT_EQ(test::read_text(c.kept), before) << c.args;
  }
  // A read-only output.
  const fs::path ro = d.dir / "ro.png";
  std::ofstream(ro) << "keep";
  fs::permissions(ro, fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  const CliResult r = test::run_cli("render " + toml + " -o " + ro.string());
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_CONTAINS(r.out, "-o " + ro.string() + " is read-only (mode 0444)");
  EXPECT_EQ(test::read_text(ro), "keep");
}

}  // namespace anamorph
