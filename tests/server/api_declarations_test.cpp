// GET /api/declarations: every declared key of the scene format, as the editor's panels read
// them, held against the C++ declarations they come from and the JSON Schema.
#include "server_fixture.h"

#include <cmath>
#include <set>

#include "camera/coins.h"
#include "camera/functions.h"
#include "camera/presets.h"
#include "scene/scene_schema.h"

namespace anamorph::test {
namespace {

class DeclarationsTest : public ServerTest {
 protected:
  json declarations() {
    const Reply r = get("/api/declarations");
    EXPECT_EQ(r.status, 200) << r.body.substr(0, 300);
    return body_of(r);
  }
};

// `got` (a list of declared keys from the API) against the C++ table `want`, key by key: names
// in order, type, whether required, and the range the reader checks (the declared one within
// the world's, with_world_range), null exactly where it is unbounded.
void expect_specs(const json& got, std::span<const ParamSpec> want, const std::string& where) {
  ASSERT_TRUE(got.is_array()) << where << ": " << got.dump().substr(0, 200);
  ASSERT_EQ(got.size(), want.size()) << where;
  for (size_t i = 0; i < want.size(); ++i) {
    const ParamSpec p = with_world_range(want[i]);
    const json& g = got[i];
    const std::string at = where + "." + std::string(p.name);
    EXPECT_EQ(g.value("name", ""), p.name) << where << "[" << i << "]";
    EXPECT_EQ(g.value("type", ""), to_string(p.type)) << at;
    EXPECT_EQ(g["required"], p.default_value.empty()) << at;
    EXPECT_EQ(g["min_exclusive"], p.min_exclusive) << at;
    EXPECT_EQ(g["max_exclusive"], p.max_exclusive) << at;
    if (std::isinf(p.min))
      EXPECT_TRUE(g["min"].is_null()) << at << ": min " << g["min"] << ", declared " << p.min;
    else
      EXPECT_EQ(g["min"], p.min) << at;
    if (std::isinf(p.max))
      EXPECT_TRUE(g["max"].is_null()) << at << ": max " << g["max"] << ", declared " << p.max;
    else
      EXPECT_EQ(g["max"], p.max) << at;
    EXPECT_EQ(g["choices"].size(), p.choices.size()) << at;
  }
}

const json* spec_named(const json& list, const std::string& name) {
  for (const json& s : list)
    if (s.value("name", "") == name) return &s;
  return nullptr;
}

TEST_F(DeclarationsTest, HasEveryPart) {
  const Reply r = get("/api/declarations");
  ASSERT_EQ(r.status, 200) << r.body.substr(0, 300);
  const json d = body_of(r);
  ASSERT_TRUE(d.is_object()) << r.body.substr(0, 300);
  for (const char* part : {"presets", "org", "dir", "coin", "camera", "image", "render", "tables"})
    EXPECT_TRUE(d.contains(part)) << part;
  for (const char* table : {"material", "object", "light", "environment", "animate"}) {
    ASSERT_TRUE(d["tables"].contains(table)) << table;
    const json& t = d["tables"][table];
    for (const char* k : {"doc", "array", "selector", "common", "variants"})
      EXPECT_TRUE(t.contains(k)) << table << " has no " << k;
  }
  EXPECT_EQ(d["tables"]["object"]["selector"], "type");
  EXPECT_TRUE(d["tables"]["object"]["variants"].contains("sphere"));
  EXPECT_EQ(d["tables"]["object"]["array"], true);
  EXPECT_EQ(d["tables"]["environment"]["array"], false);
}

TEST_F(DeclarationsTest, MatchTheCppDeclarations) {
  const json d = declarations();
  ASSERT_TRUE(d.is_object());
  expect_specs(d["coin"], coin_params(), "coin");
  expect_specs(d["camera"], camera_common_params(), "camera");
  expect_specs(d["image"], image_schema().common, "image");
  expect_specs(d["render"], render_schema().common, "render");

  ASSERT_EQ(d["presets"].size(), camera_presets().size());
  for (const PresetInfo& p : camera_presets()) {
    const std::string name(p.name);
    ASSERT_TRUE(d["presets"].contains(name)) << name;
    EXPECT_EQ(d["presets"][name]["doc"], p.doc) << name;
    expect_specs(d["presets"][name]["params"], p.params, "preset " + name);
  }
  ASSERT_EQ(d["org"].size(), org_functions().size());
  for (const auto& f : org_functions())
    expect_specs(d["org"][std::string(f.name)]["params"], f.params, "org " + std::string(f.name));
  ASSERT_EQ(d["dir"].size(), dir_functions().size());
  for (const auto& f : dir_functions())
    expect_specs(d["dir"][std::string(f.name)]["params"], f.params, "dir " + std::string(f.name));

  ASSERT_EQ(d["tables"].size(), scene_tables().size());
  for (const TableSchema* t : scene_tables()) {
    const std::string key(t->key);
    ASSERT_TRUE(d["tables"].contains(key)) << key;
    const json& g = d["tables"][key];
    EXPECT_EQ(g["array"], t->array) << key;
    EXPECT_EQ(g["selector"], t->selector) << key;
    expect_specs(g["common"], t->common, key);
    ASSERT_EQ(g["variants"].size(), t->variants.size()) << key;
    for (const TableVariant& v : t->variants) {
      const std::string name(v.name);
      ASSERT_TRUE(g["variants"].contains(name)) << key << " " << name;
      expect_specs(g["variants"][name]["params"], v.params, key + " " + name);
    }
  }
}

TEST_F(DeclarationsTest, EveryPresetOfTheJsonSchemaIsListed) {
  const json d = declarations();
  ASSERT_TRUE(d.is_object());
  const json schema = json::parse(scene_json_schema());
  std::set<std::string> in_schema;
  for (const json& branch : schema["$defs"]["camera"]["allOf"]) {
    const json& when = branch["if"];
    if (when.contains("properties") && when["properties"].contains("preset"))
      in_schema.insert(when["properties"]["preset"]["const"].get<std::string>());
  }
  EXPECT_EQ(in_schema.size(), camera_presets().size());
  for (const std::string& name : in_schema)
    EXPECT_TRUE(d["presets"].contains(name)) << "the JSON Schema's preset " << name;
  std::set<std::string> listed;
  for (const auto& [name, _] : d["presets"].items()) listed.insert(name);
  EXPECT_EQ(listed, in_schema);
}

TEST_F(DeclarationsTest, RangesAreNullExactlyWhenUnbounded) {
  const json d = declarations();
  ASSERT_TRUE(d.is_object());
  const json& persp = d["presets"]["perspective"]["params"];
  const json* fov = spec_named(persp, "fov");
  ASSERT_NE(fov, nullptr) << persp.dump().substr(0, 300);
  EXPECT_EQ((*fov)["min"], 0) << *fov;
  EXPECT_EQ((*fov)["max"], 180) << *fov;
  EXPECT_EQ((*fov)["min_exclusive"], true) << *fov;
  EXPECT_EQ((*fov)["max_exclusive"], true) << *fov;
  EXPECT_EQ((*fov)["unit"], "degrees") << *fov;
  EXPECT_EQ((*fov)["default"], "60") << *fov;
  // A position: within the world (math/input_limits.h).
  const json* from = spec_named(persp, "look_from");
  ASSERT_NE(from, nullptr);
  EXPECT_EQ((*from)["min"], -kMaxCoordinate) << *from;
  EXPECT_EQ((*from)["max"], kMaxCoordinate) << *from;
  EXPECT_EQ((*from)["min_exclusive"], false) << *from;
  // An angle without bounds.
  const json* rotation = spec_named(d["tables"]["environment"]["common"], "rotation");
  ASSERT_NE(rotation, nullptr);
  EXPECT_TRUE((*rotation)["min"].is_null()) << *rotation;
  EXPECT_TRUE((*rotation)["max"].is_null()) << *rotation;
  const json* axis = spec_named(persp, "fov_axis");
  ASSERT_NE(axis, nullptr);
  EXPECT_EQ((*axis)["choices"], json::array({"horizontal", "vertical", "diagonal"})) << *axis;
  // A coin's radius: (0, 2].
  const json* radius = spec_named(d["coin"], "radius");
  ASSERT_NE(radius, nullptr);
  EXPECT_EQ((*radius)["min"], 0) << *radius;
  EXPECT_EQ((*radius)["max"], 2) << *radius;
  EXPECT_EQ((*radius)["min_exclusive"], true) << *radius;
  EXPECT_EQ((*radius)["max_exclusive"], false) << *radius;
}

TEST_F(DeclarationsTest, OnlyGet) {
  const Reply r = post("/api/declarations", json::object());
  EXPECT_EQ(r.status, 404) << r.body.substr(0, 200);
}

}  // namespace
}  // namespace anamorph::test
