// The declared schema is the format: the docs are generated from it and held to it, every
// declared key is read (a typo of it is suggested back), every numeric key survives NaN, infinity
// and huge values with a located error or a clean load, and an independent JSON Schema validator
// accepts every example and rejects bad scenes at the key anamorph names.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "camera/coins.h"
#include "camera/functions.h"
#include "camera/presets.h"
#include "params/param_toml.h"
#include "scene/scene_loader.h"
#include "scene/scene_schema.h"
#include "scene/toml_reader.h"
#include "test_util.h"

namespace anamorph {
namespace {

namespace fs = std::filesystem;

const char* kRegenerate = "\n(regenerate: scripts/build && build/anamorph schema --docs docs)";

TEST(SchemaDocs, SceneFormatTablesAreGeneratedFromTheDeclarations) {
  const std::string md = test::read_text(test::source_dir() / "docs" / "scene-format.md");
  ASSERT_FALSE(md.empty());
  for (std::string_view block : scene_doc_blocks()) {
    const std::string want = scene_doc_block(block);
    ASSERT_FALSE(want.empty()) << block;
    EXPECT_EQ(generated_block(md, block), want)
        << "docs/scene-format.md's block " << block << " is stale" << kRegenerate;
  }
}

TEST(SchemaDocs, FunctionReferenceIsGeneratedFromTheDeclarations) {
  const std::string md = test::read_text(test::source_dir() / "docs" / "functions.md");
  EXPECT_EQ(generated_block(md, "functions"), function_reference_markdown())
      << "docs/functions.md is stale" << kRegenerate;
  // The keys no document named before it existed.
  for (const char* key : {"major_radius", "knot_type_u", "deviated_normal"})
    EXPECT_NE(md.find(key), std::string::npos) << key;
}

// Every table of the scene (each form of it), as a minimal valid scene with `body` as the
// table's text: the context a key is tried in.
struct TableCase {
  std::string label;
  std::string prefix;  // the scene text up to and including the table's header
  std::string body;    // keys the table needs besides the one tried
  std::vector<ParamSpec> keys;
  // The table's text with `key = value` and the keys it requires (a positive number each),
  // unless the key tried is one of them.
  std::string scene(std::string_view key, const std::string& value) const {
    std::string t = prefix + body;
    for (const ParamSpec& s : keys)
      if (s.default_value.empty() && s.name != key && s.type == ParamType::Number)
        t += std::string(s.name) + " = 1000\n";
    return t + std::string(key) + " = " + value + "\n";
  }
};

std::vector<ParamSpec> all_of(std::initializer_list<std::span<const ParamSpec>> groups,
                              std::string_view skip = {}) {
  std::vector<ParamSpec> out;
  for (const auto& g : groups)
    for (const ParamSpec& s : g)
      if (s.name != skip) out.push_back(s);
  return out;
}

std::vector<TableCase> table_cases() {
  std::vector<TableCase> cases = {
      {"image", "[image]\n", "", all_of({image_schema().common})},
      {"render", "[render]\n", "", all_of({render_schema().common})},
      {"environment", "[environment]\n", "", all_of({environment_schema().common}, "file")},
      {"camera", "[camera]\n", "", all_of({camera_common_params()}, "gltf_camera")},
  };
  const auto forms = [&](const TableSchema& t, const std::string& header, const std::string& extra,
                         std::initializer_list<std::string_view> skip) {
    for (const TableVariant& v : t.variants) {
      if (v.name == "mesh" || v.name == "image") continue;  // need files: tried elsewhere
      TableCase c{std::string(t.key) + " " + std::string(v.name),
                  header,
                  fmt::format("{} = \"{}\"\n{}", t.selector, v.name, extra),
                  {}};
      for (const ParamSpec& s : all_of({t.common, v.params}))
        if (s.name != t.selector && std::find(skip.begin(), skip.end(), s.name) == skip.end())
          c.keys.push_back(s);
      cases.push_back(c);
    }
  };
  forms(material_schema(), "[[material]]\n", "name = \"m\"\n", {"name"});
  forms(object_schema(), "[[object]]\n", "", {"material"});
  forms(light_schema(), "[[light]]\n", "", {});
  // The goals of `anamorph solve`, each kind with the keys it needs.
  const std::pair<std::string_view, std::string> goals[] = {
      {"pin", "point = [0, 0, -1]\nuv = [0.5, 0.5]\n"},
      {"size", "from = [0, 0, -1]\nto = [1, 0, -1]\n"},
      {"magnification", "point = [0, 0, -1]\n"},
      {"keep", ""}};
  for (const auto& [kind, body] : goals)
    cases.push_back(
        {"camera.constraint " + std::string(kind), "[[camera.constraint]]\n",
         fmt::format("kind = \"{}\"\n{}", kind, body),
         all_of({constraint_schema().common, constraint_schema().variant(kind)->params}, "kind")});
  cases.push_back({"camera.free", "[[camera.free]]\n", "key = \"camera.fov\"\n",
                   all_of({free_schema().common})});
  cases.push_back({"camera.solve", "[camera.solve]\n", "", all_of({solve_schema().common})});
  for (const PresetInfo& p : camera_presets())
    cases.push_back({"preset " + std::string(p.name), "[camera]\n",
                     fmt::format("preset = \"{}\"\n", p.name), all_of({p.params})});
  return cases;
}

std::string error_of(const std::string& toml) {
  try {
    load_scene_from_string(toml, "s.toml");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

TEST(Schema, EveryDeclaredKeyIsReadAndItsTypoSuggestedBack) {
  int tried = 0;
  for (const TableCase& c : table_cases())
    for (const ParamSpec& s : c.keys) {
      // A doubled last letter: one edit from the key, further from every other key of a table.
      const std::string typo = std::string(s.name) + s.name.back();
      const std::string e = error_of(c.scene(typo, "1"));
      EXPECT_NE(e.find(fmt::format("unknown key (did you mean '{}'?)", s.name)), std::string::npos)
          << c.label << ": " << typo << " gave: " << e;
      ++tried;
    }
  EXPECT_GT(tried, 150);
}

// The same for the keys of every camera function (those that need no other key) and coin.
TEST(Schema, EveryFunctionAndCoinKeyTypoIsSuggestedBack) {
  const auto required = [](std::span<const ParamSpec> specs) {
    return std::any_of(specs.begin(), specs.end(),
                       [](const ParamSpec& s) { return s.default_value.empty(); });
  };
  int tried = 0;
  const auto expect_suggested = [&](const std::string& scene, std::string_view key) {
    const std::string e = error_of(scene);
    EXPECT_NE(e.find(fmt::format("(did you mean '{}'?)", key)), std::string::npos)
        << scene << "gave: " << e;
    ++tried;
  };
  for (const auto& f : org_functions()) {
    if (required(f.params)) continue;
    for (const ParamSpec& s : f.params)
      expect_suggested(fmt::format("[camera]\norg = {{ type = \"{}\", {}{} = 1 }}\ndir = {{ type = "
                                   "\"normal\" }}\n",
                                   f.name, s.name, s.name.back()),
                       s.name);
  }
  for (const auto& f : dir_functions()) {
    if (required(f.params)) continue;
    for (const ParamSpec& s : f.params)
      expect_suggested(fmt::format("[camera]\norg = {{ type = \"plane\" }}\ndir = {{ type = "
                                   "\"{}\", {}{} = 1 }}\n",
                                   f.name, s.name, s.name.back()),
                       s.name);
  }
  for (const ParamSpec& s : coin_params())
    if (s.name != "position")
      expect_suggested(
          fmt::format("[[camera.coin]]\nposition = [0, 0, -1]\n{}{} = 1\n", s.name, s.name.back()),
          s.name);
  EXPECT_GT(tried, 50);
}

// NaN, infinities, huge and negative values for every numeric key of every table: a clean load
// or a SceneError naming the key, never a crash, a hang or another exception.
TEST(Schema, EveryNumericKeySurvivesNonFiniteHugeAndNegativeValues) {
  const char* values[] = {"nan", "inf", "-inf", "1e308", "-1e308", "-1", "0"};
  int rejected = 0, loaded = 0;
  for (const TableCase& c : table_cases())
    for (const ParamSpec& s : c.keys) {
      std::string (*shape)(const char*) = nullptr;
      switch (s.type) {
        case ParamType::Number:
        case ParamType::Integer:
        case ParamType::Color:
        case ParamType::Texture:
          shape = [](const char* v) { return std::string(v); };
          break;
        case ParamType::Vec2:
          shape = [](const char* v) { return fmt::format("[{0}, {0}]", v); };
          break;
        case ParamType::Vec3:
          shape = [](const char* v) { return fmt::format("[{0}, {0}, {0}]", v); };
          break;
        default:
          continue;
      }
      for (const char* v : values) {
        const std::string full = c.scene(s.name, shape(v));
        try {
          load_scene_from_string(full, "s.toml");
          ++loaded;
        } catch (const SceneError& e) {
          ++rejected;
          // Located (a value may also be refused through another key: a spot light's look_at
          // at its position leaves no direction).
          EXPECT_EQ(std::string(e.what()).rfind("s.toml:", 0), 0u)
              << c.label << " " << s.name << " = " << v << ": " << e.what();
        } catch (const std::exception& e) {
          ADD_FAILURE() << c.label << " " << s.name << " = " << v
                        << ": not a SceneError: " << e.what();
        }
      }
    }
  EXPECT_GT(rejected, 500);
  EXPECT_GT(loaded, 100);
}

TEST(Schema, DefaultsSatisfyTheirOwnDeclarations) {
  ParamTomlHooks h;
  h.fail = [](const toml::node&, std::string_view key, const std::string& msg) {
    throw std::runtime_error(std::string(key) + ": " + msg);
  };
  h.nested = [](const toml::table&, const ParamSpec&) {
    return std::shared_ptr<const NestedFunction>();
  };
  for (const TableCase& c : table_cases())
    for (const ParamSpec& s : c.keys) {
      EXPECT_FALSE(s.doc.empty()) << c.label << " " << s.name << " has no doc";
      if (s.default_value.empty() || s.default_value == "none") continue;
      const toml::table t = toml::parse("v = " + std::string(s.default_value));
      EXPECT_NO_THROW(param_from_toml(s, *t.get("v"), h)) << c.label << " " << s.name;
    }
}

// ---- against an independent validator -----------------------------------------------------

struct ShellResult {
  int code;
  std::string out;
};

ShellResult shell(const std::string& cmd) {
  FILE* p = popen((cmd + " 2>&1").c_str(), "r");
  std::string out;
  std::array<char, 4096> buf;
  size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) out.append(buf.data(), n);
  const int st = pclose(p);
  return {WIFEXITED(st) ? WEXITSTATUS(st) : -1, out};
}

bool have_validator() {
  return shell("/usr/bin/python3 -c 'import jsonschema, tomllib'").code == 0;
}

class SchemaValidator : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!have_validator())
      GTEST_SKIP() << "Debian's python3-jsonschema is not installed (scripts/install-deps "
                      "installs it): the schema is not checked by an independent validator";
    schema_ = fs::temp_directory_path() / ("anamorph_schema_" + std::to_string(getpid()));
    fs::create_directories(schema_);
    const ShellResult r =
        shell(test::binary().string() + " schema -o " + (schema_ / "s.json").string());
    ASSERT_EQ(r.code, 0) << r.out;
  }
  void TearDown() override { fs::remove_all(schema_); }
  ShellResult validate(const std::string& files) const {
    return shell("/usr/bin/python3 " +
                 (test::source_dir() / "tests/schema/validate_scenes.py").string() + " " +
                 (schema_ / "s.json").string() + " " + files);
  }
  fs::path schema_;
};

TEST_F(SchemaValidator, EveryExampleValidates) {
  std::string files;
  int n = 0;
  for (const auto& e : fs::recursive_directory_iterator(test::source_dir() / "examples"))
    if (e.path().extension() == ".toml") files += " " + e.path().string(), ++n;
  ASSERT_GT(n, 30);
  const ShellResult r = validate(files);
  EXPECT_EQ(r.code, 0) << r.out;
}

TEST_F(SchemaValidator, BadScenesAreRejectedAtTheKeyAnamorphNames) {
  // (scene, the dotted key both must name)
  const std::pair<const char*, const char*> cases[] = {
      {"[image]\nhieght = 5\n", "image.hieght"},
      {"[render]\nintegrator = \"pathh\"\n", "render.integrator"},
      {"[camera]\nfov = -1\n", "camera.fov"},
      {"[[object]]\ntype = \"sphere\"\nradius = 0\n", "object[0].radius"},
      {"[[light]]\ntype = \"point\"\nintensty = 1\n", "light[0].intensty"},
      {"[camera]\npreset = \"fisheye\"\nfvo = 3\n", "camera.fvo"},
      {"[camera]\norg = { type = \"sphere\", radiuss = 2 }\ndir = { type = \"normal\" }\n",
       "camera.org.radiuss"},
      {"[[material]]\nname = \"a\"\ncolor = { type = \"checker\", scale = -1 }\n",
       "material[0].color.scale"},
      {"[[camera.coin]]\nposition = [0, 0, -1]\nstrength = 3\n", "camera.coin[0].strength"},
      {"[environment]\nstrength = -2\n", "environment.strength"},
  };
  for (const auto& [scene, key] : cases) {
    const fs::path f = schema_ / "bad.toml";
    std::ofstream(f) << scene;
    const std::string anamorph = error_of(scene);
    EXPECT_NE(anamorph.find(std::string(": ") + key + ":"), std::string::npos)
        << "anamorph: " << anamorph;
    const ShellResult r = validate(f.string());
    EXPECT_EQ(r.code, 1) << r.out;
    // The validator names the key itself, or (for an unknown key) its table and the key.
    const std::string k = key;
    const std::string table = k.substr(0, k.rfind('.')), last = k.substr(k.rfind('.') + 1);
    const bool named = r.out.find(": " + k + ": ") != std::string::npos ||
                       (r.out.find(": " + table + ": ") != std::string::npos &&
                        r.out.find("'" + last + "' was unexpected") != std::string::npos);
    EXPECT_TRUE(named) << scene << "validator: " << r.out;
  }
}

}  // namespace
}  // namespace anamorph
