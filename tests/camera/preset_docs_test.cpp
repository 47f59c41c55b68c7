// docs/cameras.md stays in step with the presets: a section, a picture and the current parameter
// table (generated from the same ParamSpec the parser uses) for every preset.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "camera/presets.h"
#include "test_util.h"

namespace anamorph {

namespace {
const char* kRegenerate =
    "\n(regenerate: scripts/build camera_preset_gallery && build/tests/camera_preset_gallery "
    "tables docs/cameras.md)";
}  // namespace

TEST(PresetDocs, EveryPresetHasSectionPictureAndCurrentTable) {
  const auto docs = test::source_dir() / "docs";
  const std::string md = test::read_text(docs / "cameras.md");
  ASSERT_FALSE(md.empty()) << "cannot read " << docs / "cameras.md";
  for (const auto& p : camera_presets()) {
    const std::string name(p.name);
    EXPECT_NE(md.find("\n### " + name + "\n"), std::string::npos) << "no section for " << name;
    const std::string pic = "images/cameras/" + name + ".png";
    EXPECT_NE(md.find("(" + pic + ")"), std::string::npos) << "no picture for " << name;
    EXPECT_TRUE(std::filesystem::exists(docs / pic)) << docs / pic;
    const std::string open = "<!-- params:" + name + " -->\n",
                      close = "<!-- /params:" + name + " -->";
    const size_t a = md.find(open), b = md.find(close);
    ASSERT_TRUE(a != std::string::npos && b != std::string::npos && a < b)
        << "no parameter block for " << name << kRegenerate;
    EXPECT_EQ(md.substr(a + open.size(), b - a - open.size()), preset_params_markdown(p))
        << "the table of " << name << " in docs/cameras.md is stale" << kRegenerate;
  }
}

TEST(PresetDocs, ReferencedImagesExist) {
  const auto docs = test::source_dir() / "docs";
  const std::string md = test::read_text(docs / "cameras.md");
  const std::regex ref(R"(\((images/[A-Za-z0-9_/.-]+\.(png|svg))\))");
  int n = 0;
  for (auto it = std::sregex_iterator(md.begin(), md.end(), ref); it != std::sregex_iterator();
       ++it) {
    ++n;
    EXPECT_TRUE(std::filesystem::exists(docs / (*it)[1].str())) << (*it)[1].str();
  }
  EXPECT_GT(n, 20);
}

}  // namespace anamorph
