// The pin tool's solve (/api/solve, docs/solve.md "In the editor"): pins made by a known camera
// (through the server's own /api/project, coins included) give that camera back; the solved
// version re-projects every pin within the residual it reports; a save keeps the file's comments;
// stale versions and keys that are not the camera's numbers are refused.
#include "server_fixture.h"

#include <cmath>
#include <fstream>
#include <sstream>

namespace anamorph::test {
namespace {

// kScene with a coin on the sphere's right and comments to keep.
const std::string kPinScene = kScene + R"(
# the coin magnifies the sphere's right side
[[camera.coin]]
position = [0.6, 0.2, 0.6]
strength = 0.3
radius = 0.15
)";

const json kPoints = json::array({{1.0, 0.0, 0.0}, {-1.0, 0.5, 0.0}, {0.5, -0.6, 1.5}});

class SolveApi : public ServerTest {
 protected:
  void SetUp() override {
    std::string text = kPinScene;
    text.replace(text.find("fov = 50"), 8, "fov = 50  # solved by the pins");
    scene = dir.write("scene.toml", text);
    start(scene);
  }

  // The image positions of kPoints with the document as it is (one each).
  std::vector<std::array<double, 2>> projected(int64_t v) {
    std::vector<std::array<double, 2>> uv;
    for (const json& p : kPoints) {
      const Reply r = post("/api/project", json{{"position", p}, {"version", v}});
      const json b = body_of(r);
      EXPECT_EQ(r.status, 200) << r.body;
      if (b["uv"].size() != 1) ADD_FAILURE() << "not one image position: " << r.body;
      if (b["uv"].size() != 1) return {};
      uv.push_back({b["uv"][0][0].get<double>(), b["uv"][0][1].get<double>()});
    }
    return uv;
  }

  fs::path scene;
};

TEST_F(SolveApi, PinsOfAKnownCameraGiveItBackAndReprojectWithinTheResidual) {
  // The truth: fov 40, looking at (0.3, 0.2, 0); the pins are where it shows kPoints.
  const json truth = {{"key", "camera.fov"}, {"value", 40}};
  const json at = {{"key", "camera.look_at"}, {"value", {0.3, 0.2, 0.0}}};
  ASSERT_EQ(post("/api/edit", json{{"version", version()}, {"edits", {truth, at}}}).status, 200);
  const auto target = projected(version());
  ASSERT_EQ(target.size(), 3u);
  ASSERT_EQ(post("/api/undo", json::object()).status, 200);  // back to fov 50, look_at 0

  json pins = json::array();
  for (size_t i = 0; i < 3; ++i)
    pins.push_back({{"kind", "pin"}, {"point", kPoints[i]}, {"uv", target[i]}});
  const int64_t v0 = version();
  const Reply r =
      post("/api/solve", json{{"version", v0},
                              {"constraints", pins},
                              {"free", {"camera.fov", "camera.look_at.0", "camera.look_at.1"}},
                              {"apply", true}});
  ASSERT_EQ(r.status, 200) << r.body;
  const json b = body_of(r);
  EXPECT_TRUE(b["met"].get<bool>()) << r.body;
  ASSERT_EQ(b["version"].get<int64_t>(), v0 + 1);
  const double want[] = {40, 0.3, 0.2};
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(b["values"][k]["value"].get<double>(), want[k], 1e-6) << b["values"][k].dump();
  EXPECT_NEAR(b["state"]["document"]["camera"]["fov"].get<double>(), 40, 1e-6);
  EXPECT_FALSE(b["state"]["document"]["camera"].contains("constraint")) << "goals not written";

  // The solved version shows each point within its reported residual (pixels of 64 x 48).
  const auto now = projected(v0 + 1);
  ASSERT_EQ(now.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    const double px = std::hypot((now[i][0] - target[i][0]) * 64, (now[i][1] - target[i][1]) * 48);
    const double reported = b["constraints"][i]["residual"].get<double>();
    EXPECT_LE(px, reported + 1e-9) << "pin " << i;
    EXPECT_LT(reported, 1e-4) << "pin " << i;
  }

  // Saved: the solved fov, the file's comments kept.
  ASSERT_EQ(post("/api/save", json::object()).status, 200);
  std::stringstream saved;
  saved << std::ifstream(scene).rdbuf();
  EXPECT_NE(saved.str().find("# solved by the pins"), std::string::npos) << saved.str();
  EXPECT_NE(saved.str().find("# the coin magnifies"), std::string::npos) << saved.str();
  EXPECT_EQ(saved.str().find("constraint"), std::string::npos) << saved.str();
}

TEST_F(SolveApi, StaleVersionsAndKeysThatAreNotCameraNumbersAreRefused) {
  const json pin = {{"kind", "pin"}, {"point", kPoints[0]}, {"uv", {0.5, 0.5}}};
  const int64_t v = version();
  Reply r = post("/api/solve",
                 json{{"version", v + 5}, {"constraints", {pin}}, {"free", {"camera.fov"}}});
  EXPECT_EQ(r.status, 409) << r.body;
  r = post("/api/solve", json{{"version", v}, {"constraints", {pin}}, {"free", {"camera.preset"}}});
  EXPECT_EQ(r.status, 400) << r.body;
  EXPECT_NE(body_of(r).value("key", "").find("camera.free"), std::string::npos) << r.body;
  r = post("/api/solve",
           json{{"version", v}, {"constraints", json::array()}, {"free", {"camera.fov"}}});
  EXPECT_EQ(r.status, 400) << r.body;
  EXPECT_EQ(version(), v) << "nothing was applied";
}

}  // namespace
}  // namespace anamorph::test
