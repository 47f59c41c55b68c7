// Editing the document through the API: versions, the scene reader's own messages for bad keys
// and values, two tabs, removal, undo and redo.
#include "server_fixture.h"

#include "scene/toml_reader.h"

namespace anamorph::test {
namespace {

using EditTest = ServerTest;

TEST_F(EditTest, EditMakesANewVersionAndShowsInTheState) {
  const int64_t v = version();
  const Reply r = edit("camera.fov", 70, v);
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(body_of(r)["version"], v + 1) << r.body;
  const json s = state();
  EXPECT_EQ(s["version"], v + 1);
  EXPECT_EQ(s["document"]["camera"]["fov"], 70) << s["document"]["camera"].dump();
  EXPECT_NE(s["text"].get<std::string>().find("fov = 70"), std::string::npos) << s["text"];
  EXPECT_EQ(s["can_undo"], true);
}

TEST_F(EditTest, OutOfRangeValueGetsTheSceneReadersMessage) {
  std::string expected;
  try {
    load_scene_from_string(kScene, dir.path() / "scene.toml", {"camera.fov=500"});
    ADD_FAILURE() << "the scene reader took camera.fov = 500";
  } catch (const SceneError& e) {
    expected = e.message;
  }
  const json before = state()["document"];
  const Reply r = edit("camera.fov", 500, version());
  EXPECT_EQ(r.status, 400) << r.body;
  EXPECT_EQ(body_of(r)["key"], "camera.fov") << r.body;
  EXPECT_EQ(body_of(r)["error"], expected) << r.body;
  EXPECT_EQ(state()["document"], before);
  EXPECT_EQ(version(), 1);
}

TEST_F(EditTest, UnknownKeySuggestsTheNearestOne) {
  const Reply r = edit("camera.fvo", 70, version());
  EXPECT_EQ(r.status, 400) << r.body;
  const std::string message = body_of(r).value("error", "");
  EXPECT_NE(message.find("did you mean"), std::string::npos) << r.body;
  EXPECT_NE(message.find("fov"), std::string::npos) << r.body;
  EXPECT_FALSE(state()["document"]["camera"].contains("fvo"));
}

TEST_F(EditTest, NonFiniteAndEmptyEditsAre400) {
  const int64_t v = version();
  const Reply no_key =
      post("/api/edit", json{{"version", v}, {"edits", json::array({json{{"value", 1}}})}});
  EXPECT_EQ(no_key.status, 400) << no_key.body;
  const Reply null_in_array = edit("camera.look_at", json::array({0, nullptr, 0}), v);
  EXPECT_EQ(null_in_array.status, 400) << null_in_array.body;
  EXPECT_EQ(version(), v);
}

// A malformed body's message quotes its bytes, which need not be UTF-8 (found by fuzz_api: the
// answer's JSON could not be written, and the request got a 500 instead of its 400).
TEST_F(EditTest, BodiesThatAreNotUtf8GetA400WithAMessage) {
  const int64_t v = version();
  for (const std::string& body :
       {std::string("{\"version\": 1, \"e\xff\xfe\": [}"), std::string("\xc3\x28{\"version\": 1}"),
        std::string("{\"version\":1,\"edits\":[{\"key\":\"a\x80\"}]}")}) {
    const Reply r = post("/api/edit", body);
    EXPECT_EQ(r.status, 400) << r.body;
    EXPECT_FALSE(body_of(r).value("error", "").empty()) << r.body;
  }
  EXPECT_EQ(version(), v);
}

TEST_F(EditTest, StaleVersionIs409AndTheFirstWriterWins) {
  const int64_t v = version();
  // Two tabs loaded version v; the first one's edit goes in, the second's is refused.
  const Reply first = edit("camera.fov", 60, v);
  ASSERT_EQ(first.status, 200) << first.body;
  const Reply second = edit("camera.fov", 40, v);
  EXPECT_EQ(second.status, 409) << second.body;
  EXPECT_EQ(body_of(second)["version"], v + 1) << second.body;
  const json s = state();
  EXPECT_EQ(s["version"], v + 1);
  EXPECT_EQ(s["document"]["camera"]["fov"], 60);
  // A version from the future is as stale.
  EXPECT_EQ(edit("camera.fov", 40, v + 7).status, 409);
}

TEST_F(EditTest, NullRemovesAKey) {
  ASSERT_TRUE(state()["document"]["render"].contains("max_depth"));
  const Reply r = edit("render.max_depth", nullptr, version());
  ASSERT_EQ(r.status, 200) << r.body;
  const json s = state();
  EXPECT_FALSE(s["document"]["render"].contains("max_depth")) << s["document"]["render"].dump();
  EXPECT_EQ(s["text"].get<std::string>().find("max_depth"), std::string::npos) << s["text"];
}

TEST_F(EditTest, UndoAndRedoRestoreTheDocuments) {
  const json d1 = state()["document"];
  ASSERT_EQ(edit("camera.fov", 65, version()).status, 200);
  ASSERT_EQ(edit("object.0.radius", 0.5, version()).status, 200);
  const json d3 = state()["document"];
  const int64_t v3 = version();

  Reply r = post("/api/undo", json::object());
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(body_of(r)["version"], v3 + 1);
  const json d2 = state()["document"];
  EXPECT_EQ(d2["camera"]["fov"], 65);
  EXPECT_EQ(d2["object"][0]["radius"], 1.0);
  ASSERT_EQ(post("/api/undo", json::object()).status, 200);
  EXPECT_EQ(state()["document"], d1);
  EXPECT_EQ(state()["can_undo"], false);
  r = post("/api/undo", json::object());
  EXPECT_EQ(r.status, 409) << r.body;  // (a state the document is not in: a conflict)
  EXPECT_NE(body_of(r).value("error", "").find("undo"), std::string::npos) << r.body;

  ASSERT_EQ(post("/api/redo", json::object()).status, 200);
  EXPECT_EQ(state()["document"], d2);
  ASSERT_EQ(post("/api/redo", json::object()).status, 200);
  EXPECT_EQ(state()["document"], d3);
  EXPECT_EQ(post("/api/redo", json::object()).status, 409);

  // A new edit after an undo drops what could be redone.
  ASSERT_EQ(post("/api/undo", json::object()).status, 200);
  ASSERT_EQ(edit("camera.fov", 30, version()).status, 200);
  EXPECT_EQ(state()["can_redo"], false);
  EXPECT_EQ(post("/api/redo", json::object()).status, 409);
}

TEST_F(EditTest, NothingToUndoOnAFreshDocument) {
  const Reply r = post("/api/undo", json::object());
  EXPECT_EQ(r.status, 409) << r.body;
  EXPECT_EQ(body_of(r)["version"], 1) << r.body;
  EXPECT_EQ(post("/api/redo", std::string()).status, 409);
}

}  // namespace
}  // namespace anamorph::test
