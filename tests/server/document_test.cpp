// The document's pure parts: floats written in their shortest exact form, and telling a change
// of the view from a change of the scene.
#include <bit>
#include <cmath>
#include <random>
#include <sstream>

#include <gtest/gtest.h>

#include "scene/toml_edit.h"
#include "scene/toml_reader.h"
#include "server/document.h"
#include "server_fixture.h"

namespace anamorph::test {
namespace {

using server::differs_only_in_view;
using server::tidy_floats;

TEST(TidyFloats, ShortensFloatsToTheirShortestForm) {
  EXPECT_EQ(tidy_floats("a = 0.80000000000000004\n"), "a = 0.8\n");
  EXPECT_EQ(tidy_floats("a = -0.80000000000000004\n"), "a = -0.8\n");
  EXPECT_EQ(tidy_floats("v = [0.10000000000000001, 0.20000000000000001, 1.0]\n"),
            "v = [0.1, 0.2, 1.0]\n");
  EXPECT_EQ(tidy_floats("a = 0.30000000000000004\n"), "a = 0.30000000000000004\n");
  EXPECT_EQ(tidy_floats("a = 2.0000000000000000\n"), "a = 2.0\n");
  EXPECT_EQ(tidy_floats("a = 1.0000000000000001e+300\n"), "a = 1e+300\n");
  EXPECT_EQ(tidy_floats("t = { x = 0.50000000000000000, y = 3 }\n"), "t = { x = 0.5, y = 3 }\n");
}

TEST(TidyFloats, LeavesStringsIntegersAndDatesAlone) {
  for (const std::string text : {
           "s = \"0.80000000000000004\"\n",
           "s = 'x 0.80000000000000004 y'\n",
           "s = \"a \\\"0.80000000000000004\\\" b\"\n",
           "n = 42\nm = -17\nh = 0xDEAD\nb = 1_000\no = 0o17\n",
           "key2 = 1\nx_0 = 2\n",
           "d = 1979-05-27\n",
           "dt = 1979-05-27T07:32:00Z\n",
           "t = 07:32:00\n",
           "dt = 1979-05-27T00:32:00-07:00\n",
           "t = 07:32:00.5\n",
           "dt = 1979-05-27T00:32:00.999999-07:00\n",
           "dt = 1979-05-27 07:32:01.25\n",
       })
    EXPECT_EQ(tidy_floats(text), text);
}

TEST(TidyFloats, WhatTomlWritesReadsBackUnchanged) {
  toml::table t;
  t.insert("s", "0.80000000000000004\n1.5 \"quoted\" 'single'");
  t.insert("when", toml::date_time{toml::date{1979, 5, 27}, toml::time{7, 32, 1, 250000000}});
  t.insert("at", toml::time{7, 32, 0, 500000000});
  t.insert("n", 12345678901234);
  t.insert("x", 0.1 + 0.7);
  const std::string text = tidy_floats(to_toml_text(t));
  const toml::table back = toml::parse(text);
  EXPECT_EQ(back, t) << text;
  EXPECT_NE(text.find("0.7999999999999999"), std::string::npos) << text;
}

// Random doubles of every magnitude (random bit patterns, finite ones) read back bit for bit.
TEST(TidyFloats, RoundTripIsExact) {
  std::mt19937_64 rng(20240611);
  std::uniform_real_distribution<double> unit(-1, 1);
  int checked = 0;
  for (int i = 0; i < 20000; ++i) {
    const double x = i % 2 ? std::bit_cast<double>(rng()) : unit(rng) * std::pow(10, i % 40 - 20);
    if (!std::isfinite(x)) continue;
    toml::table t;
    t.insert("a", x);
    t.insert("v", toml::array{x, -x, x / 3});
    const std::string text = tidy_floats(to_toml_text(t));
    toml::table back;
    try {
      back = toml::parse(text);
    } catch (const toml::parse_error& e) {
      ADD_FAILURE() << "not TOML after tidy_floats: " << text << " (" << e.description() << ")";
      continue;
    }
    const double a = back["a"].value_or(std::nan("")), v1 = back["v"][1].value_or(std::nan("")),
                 v2 = back["v"][2].value_or(std::nan(""));
    ASSERT_EQ(std::bit_cast<uint64_t>(a), std::bit_cast<uint64_t>(x))
        << std::hexfloat << x << " -> " << text;
    ASSERT_EQ(std::bit_cast<uint64_t>(v1), std::bit_cast<uint64_t>(-x)) << text;
    ASSERT_EQ(std::bit_cast<uint64_t>(v2), std::bit_cast<uint64_t>(x / 3)) << text;
    ++checked;
  }
  EXPECT_GT(checked, 15000);
}

TEST(Document, ViewOnlyChangesAreTold) {
  const toml::table a = toml::parse(kScene);
  EXPECT_TRUE(differs_only_in_view(a, a));
  auto changed = [&](const std::string& key, const std::string& value) {
    toml::table b = a;
    set_path(b, key, *parse_value_text(value).get("v"), {"test"});
    return b;
  };
  EXPECT_TRUE(differs_only_in_view(a, changed("camera.fov", "70")));
  EXPECT_TRUE(differs_only_in_view(a, changed("camera.preset", "\"fisheye\"")));
  EXPECT_TRUE(differs_only_in_view(a, changed("image.width", "32")));
  EXPECT_TRUE(differs_only_in_view(a, changed("render.spp", "4")));
  EXPECT_FALSE(differs_only_in_view(a, changed("object.0.radius", "0.5")));
  EXPECT_FALSE(differs_only_in_view(a, changed("material.0.color", "[0.1, 0.2, 0.3]")));
  EXPECT_FALSE(differs_only_in_view(a, changed("light.0.position", "[1, 2, 3]")));
  EXPECT_FALSE(differs_only_in_view(a, changed("environment.color", "[0.1, 0.1, 0.1]")));
  toml::table fewer = a;
  fewer.erase("light");
  EXPECT_FALSE(differs_only_in_view(a, fewer));
}

TEST(Document, EditsUndoAndRedoCountVersions) {
  TempFolder dir;
  server::Document d(dir.write("s.toml", kScene));
  EXPECT_EQ(d.version(), 1);
  EXPECT_FALSE(d.can_undo());
  const server::KeyEdit edits[] = {{"camera.fov", "70"}, {"render.max_depth", std::nullopt}};
  d.commit(d.edited(edits));
  EXPECT_EQ(d.version(), 2);
  EXPECT_EQ(d.table()["camera"]["fov"].value<int64_t>(), 70);
  EXPECT_FALSE(d.table()["render"]["max_depth"]);
  EXPECT_TRUE(d.undo());
  EXPECT_EQ(d.version(), 3);
  EXPECT_EQ(d.table(), toml::parse(kScene));
  EXPECT_TRUE(d.redo());
  EXPECT_EQ(d.table()["camera"]["fov"].value<int64_t>(), 70);
  EXPECT_FALSE(d.redo());
  const server::KeyEdit bad[] = {{"object.7.radius", "1"}};
  EXPECT_THROW(d.edited(bad), SceneError);
}

}  // namespace
}  // namespace anamorph::test
