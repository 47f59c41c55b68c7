// The editor reads and writes files only in the scene's folder: model files named by edits, and
// saved scenes (no paths, no symbolic links, only .toml). What it saves is the scene it shows.
#include "server_fixture.h"

namespace anamorph::test {
namespace {

const std::string kTriangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

class FilesTest : public ServerTest {
 protected:
  // The scene in dir/scene/ (so that dir itself is "outside"), with a mesh from tri.obj.
  void SetUp() override {
    dir.write("scene/tri.obj", kTriangle);
    dir.write("scene/other.obj", kTriangle);
    dir.write("outside.obj", kTriangle);
    start(dir.write("scene/scene.toml", kScene +
                                            "\n[[object]]\ntype = \"mesh\"\nfile = \"tri.obj\"\n"
                                            "transform = { translate = [2.0, 0.0, 0.0] }\n"));
  }
  fs::path folder() const { return dir.path() / "scene"; }
  // The message of a refused edit of the mesh's file name.
  void expect_refused_file(const std::string& file) {
    const Reply r = edit("object.2.file", file, version());
    EXPECT_EQ(r.status, 400) << file << ": " << r.body;
    EXPECT_NE(body_of(r).value("error", "").find(folder().string()), std::string::npos)
        << file << ": " << r.body;
    EXPECT_EQ(state()["document"]["object"][2]["file"], "tri.obj");
  }
};

TEST_F(FilesTest, EditsMayNameFilesOnlyInTheScenesFolder) {
  ASSERT_EQ(editor->folder(), folder());
  expect_refused_file("../outside.obj");
  expect_refused_file((dir.path() / "outside.obj").string());
  expect_refused_file("/etc/passwd");
  fs::create_symlink(dir.path() / "outside.obj", folder() / "link.obj");
  expect_refused_file("link.obj");
  fs::create_directories(folder() / "sub");
  expect_refused_file("sub/../../outside.obj");
  // A file in the folder is fine.
  const Reply ok = edit("object.2.file", "other.obj", version());
  EXPECT_EQ(ok.status, 200) << ok.body;
}

TEST_F(FilesTest, SaveRefusesPathsSymlinksAndOtherExtensions) {
  fs::create_directories(folder() / "sub");
  const fs::path outside_abs = dir.path() / "abs.toml";
  const std::vector<std::pair<std::string, fs::path>> refused = {
      {"../x.toml", dir.path() / "x.toml"},
      {outside_abs.string(), outside_abs},
      {"sub/x.toml", folder() / "sub" / "x.toml"},
      {"x.txt", folder() / "x.txt"},
      {"..", dir.path() / ".toml"},
      {"x", folder() / "x"}};
  for (const auto& [name, where] : refused) {
    const Reply r = post("/api/save", json{{"name", name}});
    EXPECT_EQ(r.status, 400) << name << ": " << r.body;
    EXPECT_TRUE(body_of(r).contains("error")) << name << ": " << r.body;
    EXPECT_FALSE(fs::exists(where)) << name << " wrote " << where;
  }
  EXPECT_EQ(post("/api/save", json{{"name", 7}}).status, 400);
  // A NUL ends the name the system sees: this one would overwrite the model.
  const std::string before = read_text(folder() / "tri.obj");
  const Reply nul = post("/api/save", json{{"name", std::string("tri.obj\0.toml", 13)}});
  EXPECT_EQ(nul.status, 400) << nul.body;
  EXPECT_EQ(read_text(folder() / "tri.obj"), before);

  const fs::path target = dir.write("target.toml", "# not the editor's\n");
  fs::create_symlink(target, folder() / "link.toml");
  const Reply r = post("/api/save", json{{"name", "link.toml"}});
  EXPECT_EQ(r.status, 400) << r.body;
  EXPECT_EQ(read_text(target), "# not the editor's\n");
  EXPECT_TRUE(fs::is_symlink(folder() / "link.toml"));
}

TEST_F(FilesTest, SavedCopyRendersAsTheDocument) {
  // Values whose shortest decimal forms have from 1 to 17 digits.
  ASSERT_EQ(edit("camera.look_from", json::array({0.1, 0.1 + 0.2, 5.3}), version()).status, 200);
  ASSERT_EQ(edit("object.0.radius", 0.7, version()).status, 200);
  ASSERT_EQ(edit("camera.fov", 1.0 / 3 * 150, version()).status, 200);
  const Reply r = post("/api/save", json{{"name", "copy.toml"}});
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(body_of(r)["saved"], "copy.toml");

  const std::string saved = read_text(folder() / "copy.toml");
  EXPECT_EQ(saved, state()["text"].get<std::string>());
  EXPECT_NE(saved.find("radius = 0.7\n"), std::string::npos) << saved;
  const Scene copy = load_scene(folder() / "copy.toml");
  // The same edits as overrides of the original file, read by the scene reader.
  const Scene document = load_scene(
      folder() / "scene.toml", {"camera.look_from=[0.1, 0.30000000000000004, 5.3]",
                                "object.0.radius=0.7", "camera.fov=" + json(1.0 / 3 * 150).dump()});
  const std::vector<unsigned char> a = render_rgba8(copy), b = render_rgba8(document);
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a.size(), size_t(64 * 48 * 4));
  size_t differing = 0, first = a.size();
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i] != b[i]) {
      ++differing;
      first = std::min(first, i);
    }
  EXPECT_EQ(differing, 0u) << "first at byte " << first << " (pixel " << first / 4 << ")";
  // The render is not empty: the sphere is there.
  EXPECT_NE(std::count(a.begin(), a.end(), 0), std::ptrdiff_t(a.size()));
}

TEST_F(FilesTest, SaveWithoutANameWritesTheSceneFile) {
  ASSERT_EQ(edit("camera.fov", 72, version()).status, 200);
  const Reply r = post("/api/save", json::object());
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(body_of(r)["saved"], "scene.toml");
  const Scene s = load_scene(folder() / "scene.toml");
  EXPECT_EQ(read_text(folder() / "scene.toml"), state()["text"].get<std::string>());
  EXPECT_NE(read_text(folder() / "scene.toml").find("fov = 72\n"), std::string::npos);
  EXPECT_NE(s.camera_toml.find("fov = 72"), std::string::npos) << s.camera_toml;
}

TEST_F(FilesTest, UndoToAStateThatNoLongerLoadsChangesNothing) {
  ASSERT_EQ(edit("object.2.file", "other.obj", version()).status, 200);
  fs::remove(folder() / "tri.obj");
  const json before = state();
  const Reply r = post("/api/undo", json::object());
  EXPECT_EQ(r.status, 400) << r.body;
  EXPECT_NE(body_of(r).value("error", "").find("tri.obj"), std::string::npos) << r.body;
  const json after = state();
  EXPECT_EQ(after["version"], before["version"]);
  EXPECT_EQ(after["document"], before["document"]);
  EXPECT_EQ(after["can_undo"], true);
  // Once the file is back, the same undo goes through.
  dir.write("scene/tri.obj", kTriangle);
  const Reply again = post("/api/undo", json::object());
  EXPECT_EQ(again.status, 200) << again.body;
  EXPECT_EQ(body_of(again)["version"], before["version"].get<int64_t>() + 1) << again.body;
  EXPECT_EQ(state()["document"]["object"][2]["file"], "tri.obj");
}

class IncludeTest : public ServerTest {
 protected:
  void SetUp() override {
    dir.write("base.toml", kScene);
    start(dir.write("main.toml", "include = \"base.toml\"\n\n[camera]\nfov = 45\n"));
  }
};

TEST_F(IncludeTest, SavedSceneKeepsItsInclude) {
  ASSERT_EQ(edit("camera.fov", 35, version()).status, 200);
  ASSERT_EQ(post("/api/save", json::object()).status, 200);
  const std::string saved = read_text(dir.path() / "main.toml");
  EXPECT_EQ(toml::parse(saved)["include"].value_or(std::string()), "base.toml") << saved;
  EXPECT_EQ(saved.find("[[object]]"), std::string::npos) << saved;
  EXPECT_EQ(saved.find("material"), std::string::npos) << saved;
  EXPECT_EQ(read_text(dir.path() / "base.toml"), kScene);
  const Scene s = load_scene(dir.path() / "main.toml");
  EXPECT_EQ(s.render.width, 64);
  EXPECT_EQ(s.shapes.size(), 2u);  // the included sphere and floor
  EXPECT_NE(s.camera_toml.find("fov = 35"), std::string::npos) << s.camera_toml;
}

}  // namespace
}  // namespace anamorph::test
