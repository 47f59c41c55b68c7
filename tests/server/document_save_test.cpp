// Saving the document as text: the file's own text with the edits spliced in (comments, order
// and layout kept), and whatever cannot be spliced written whole; either way the text reads back
// as the document.
#include <random>
#include <sstream>

#include <gtest/gtest.h>

#include "scene/toml_edit.h"
#include "server/document_save.h"

namespace anamorph::test {
namespace {

using server::saved_text;

const std::string kScene = R"(# A scene with comments.
include = "world.toml"  # the floor and the lights

[image]
width = 640   # pixels
height = 480

# The camera.
[camera]
preset = "perspective"
fov = 55
look_from = [0.0, 2.2,
             7.5]  # (an array over two lines)

[[object]]
type = "sphere"   # first
radius = 0.8

[[object]]
type = "box"
size = [1, 2, 3]

[[light]]
type = "point"
position = [4.0, 6.0, 5.0]
)";

toml::table edited(const std::string& text,
                   const std::vector<std::pair<std::string, std::optional<std::string>>>& edits) {
  toml::table t = toml::parse(text);
  for (const auto& [key, value] : edits) {
    if (value)
      set_path(t, key, *parse_value_text(*value).get("v"), {});
    else
      remove_path(t, key);
  }
  return t;
}

// The lines of `a` missing from `b`.
std::vector<std::string> lines_missing(const std::string& a, const std::string& b) {
  std::vector<std::string> out;
  std::istringstream in(a);
  for (std::string line; std::getline(in, line);)
    if (b.find(line) == std::string::npos) out.push_back(line);
  return out;
}

TEST(SavedText, AnEditedValueChangesOnlyItsOwnText) {
  const toml::table t = edited(kScene, {{"camera.fov", "70"}, {"image.width", "800"}});
  const auto s = saved_text(kScene, t);
  EXPECT_FALSE(s.normalized);
  std::string expected = kScene;
  expected.replace(expected.find("fov = 55"), 8, "fov = 70");
  expected.replace(expected.find("width = 640"), 11, "width = 800");
  EXPECT_EQ(s.text, expected);
}

TEST(SavedText, MultiLineValuesAndStringsAreReplacedWhole) {
  const toml::table t =
      edited(kScene, {{"camera.look_from", "[1, 2, 3]"}, {"camera.preset", "\"fisheye\""}});
  const auto s = saved_text(kScene, t);
  EXPECT_FALSE(s.normalized);
  EXPECT_NE(s.text.find("look_from = [ 1, 2, 3 ]  # (an array over two lines)"), std::string::npos)
      << s.text;
  EXPECT_NE(s.text.find("preset = \"fisheye\""), std::string::npos) << s.text;
  EXPECT_EQ(toml::parse(s.text), t);
}

TEST(SavedText, KeysAreAddedToTheirTableAndRemovedWithTheirLine) {
  const toml::table t = edited(kScene, {{"camera.up", "[0, 0, 1]"},
                                        {"image.height", std::nullopt},
                                        {"object.0.radius", std::nullopt}});
  const auto s = saved_text(kScene, t);
  EXPECT_FALSE(s.normalized);
  EXPECT_EQ(toml::parse(s.text), t);
  EXPECT_EQ(s.text.find("height = 480"), std::string::npos);
  EXPECT_EQ(s.text.find("radius = 0.8"), std::string::npos);
  // The new key follows the camera's last line, before the next block.
  const size_t up = s.text.find("up = [ 0, 0, 1 ]");
  ASSERT_NE(up, std::string::npos) << s.text;
  EXPECT_LT(s.text.find("7.5]"), up);
  EXPECT_LT(up, s.text.find("[[object]]"));
  // Every comment is still there.
  for (const std::string& line : lines_missing(kScene, s.text))
    EXPECT_TRUE(line.find('#') == std::string::npos || line.find("radius") != std::string::npos ||
                line.find("height") != std::string::npos)
        << "lost: " << line;
}

TEST(SavedText, NewTablesAndEntriesAreAppendedAsBlocks) {
  const toml::table t = edited(
      kScene, {{"camera.coin", "[{ position = [0, 0.5, 2], strength = 0.5 }]"},
               {"object",
                "[{ type = \"sphere\", radius = 0.8 }, { type = \"box\", size = [1, 2, 3] }, "
                "{ type = \"disk\", radius = 2 }]"},
               {"environment", "{ color = [0.2, 0.3, 0.4] }"}});
  const auto s = saved_text(kScene, t);
  EXPECT_FALSE(s.normalized) << s.text;
  EXPECT_EQ(toml::parse(s.text), t);
  EXPECT_TRUE(lines_missing(kScene, s.text).empty()) << s.text;
  // (A table set by an edit is an inline value, written where the file's keys are.)
  for (const char* block : {"[[camera.coin]]", "environment = {", "type = \"disk\""})
    EXPECT_NE(s.text.find(block), std::string::npos) << block << " in\n" << s.text;
}

TEST(SavedText, RemovedBlocksGoWithTheirLines) {
  const toml::table t = edited(kScene, {{"object.1", std::nullopt}, {"light", std::nullopt}});
  const auto s = saved_text(kScene, t);
  EXPECT_FALSE(s.normalized) << s.text;
  EXPECT_EQ(toml::parse(s.text), t);
  EXPECT_EQ(s.text.find("type = \"box\""), std::string::npos) << s.text;
  EXPECT_EQ(s.text.find("[[light]]"), std::string::npos) << s.text;
  EXPECT_NE(s.text.find("# first"), std::string::npos);
}

TEST(SavedText, KeysWrittenAsDottedKeysFallBackToAWholeRewrite) {
  const std::string text = "camera.fov = 55\ncamera.preset = \"fisheye\"\n";
  const toml::table t = edited(text, {{"camera.tilt", "10"}});
  const auto s = saved_text(text, t);
  EXPECT_EQ(toml::parse(s.text), t) << s.text;
}

TEST(SavedText, ColumnsCountCharactersNotBytes) {
  const std::string text = "[camera]\n\"nom ä ö ü\" = 1\nfov = 55 # «ça»\n";
  const toml::table t = edited(text, {{"camera.nom ä ö ü", "2"}});
  const auto s = saved_text(text, t);
  EXPECT_FALSE(s.normalized);
  EXPECT_EQ(s.text, "[camera]\n\"nom ä ö ü\" = 2\nfov = 55 # «ça»\n");
}

// Found by fuzz_save: a new table under the empty key "" at the top level (a block whose parent
// path is empty) was read as a block with no key, past the end of an empty path.
TEST(SavedText, EmptyKeysAtTheTopLevel) {
  const std::string text = "x = 1\n";
  toml::table t = toml::parse(text);
  toml::table inner;
  inner.insert("a", 1);
  inner.is_inline(false);
  t.insert("", inner);
  t.insert("y", toml::array{toml::table{{"b", 2}}});
  const auto s = saved_text(text, t);
  EXPECT_TRUE(s.reads_back);
  EXPECT_EQ(toml::parse(s.text), t) << s.text;
  EXPECT_EQ(s.text.rfind("x = 1\n", 0), 0u) << s.text;
}

// Random edits of a real scene: the text always reads back as the document, and only the rare
// edits that cannot be spliced rewrite it.
TEST(SavedText, RandomEditsAlwaysReadBack) {
  std::mt19937 rng(7);
  const std::vector<std::pair<std::string, std::optional<std::string>>> pool = {
      {"camera.fov", "33"},
      {"camera.up", "[0, 1, 0.1]"},
      {"camera.fov", std::nullopt},
      {"image.width", "123"},
      {"object.0.radius", "2.5"},
      {"object.1.size", "[2, 2, 2]"},
      {"object.1", std::nullopt},
      {"light", std::nullopt},
      {"camera.coin", "[{ position = [1, 2, 3] }]"},
      {"render", "{ spp = 4 }"},
      {"camera.look_from", std::nullopt},
      {"object.0.material", "\"gold\""}};
  int spliced = 0;
  for (int run = 0; run < 300; ++run) {
    toml::table t = toml::parse(kScene);
    const int n = 1 + int(rng() % 4);
    for (int i = 0; i < n; ++i) {
      const auto& [key, value] = pool[rng() % pool.size()];
      try {
        if (value)
          set_path(t, key, *parse_value_text(*value).get("v"), {});
        else
          remove_path(t, key);
      } catch (const std::exception&) {  // (an index that no longer exists)
      }
    }
    const auto s = saved_text(kScene, t);
    ASSERT_EQ(toml::parse(s.text), t) << "run " << run << ":\n" << s.text;
    spliced += s.normalized ? 0 : 1;
  }
  EXPECT_GT(spliced, 250) << "most edits keep the file's text";
}

}  // namespace
}  // namespace anamorph::test
