// The scene file reader: strictness, error locations, overrides and includes.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "scene/scene_loader.h"
#include "scene/toml_reader.h"
#include "test_util.h"

namespace anamorph {

namespace {

// Loads `text` and returns the error message ("" when it loads).
std::string error_of(const std::string& text, const std::vector<std::string>& overrides = {}) {
  try {
    load_scene_from_string(text, "test.toml", overrides);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

void expect_contains(const std::string& msg, const std::string& part) {
  EXPECT_NE(msg.find(part), std::string::npos)
      << "message: " << msg << "\nexpected to contain: " << part;
}

double horizontal_fov_degrees(const Scene& s) {
  const auto a = s.camera->generate({{0.0, 0.5}}), b = s.camera->generate({{1.0, 0.5}});
  return degrees(std::acos(dot(a->dir, b->dir)));
}

}  // namespace

TEST(SceneParser, DefaultsWhenEmpty) {
  const Scene s = load_scene_from_string("", "empty.toml");
  EXPECT_EQ(s.render.width, 640);
  EXPECT_EQ(s.render.height, 480);
  EXPECT_EQ(s.render.integrator, "whitted");
  EXPECT_EQ(s.render.view, View::Beauty);
  ASSERT_TRUE(s.camera);
  EXPECT_NEAR(horizontal_fov_degrees(s), 60, 1e-9);
}

TEST(SceneParser, UnknownKeyNamesLineColumnAndSuggests) {
  const std::string msg = error_of("[camera]\nfov = 60\nlok_at = [0, 0, 0]\n");
  expect_contains(msg, "test.toml:3:1");
  expect_contains(msg, "camera.lok_at");
  expect_contains(msg, "did you mean 'look_at'");
}

TEST(SceneParser, UnknownTopLevelTable) {
  const std::string msg = error_of("[imgae]\nwidth = 3\n");
  expect_contains(msg, "imgae");
  expect_contains(msg, "did you mean 'image'");
}

TEST(SceneParser, WrongTypeIsAnError) {
  const std::string msg = error_of("[camera]\nfov = \"wide\"\n");
  expect_contains(msg, "test.toml:2:7");
  expect_contains(msg, "camera.fov");
  expect_contains(msg, "expected a number");
}

TEST(SceneParser, OutOfRangeAndNonFinite) {
  expect_contains(error_of("[camera]\nfov = 180\n"), "out of range");
  expect_contains(error_of("[camera]\nfov = 0\n"), "out of range");
  expect_contains(error_of("[camera]\nfov = nan\n"), "finite");
  expect_contains(error_of("[image]\nwidth = -3\n"), "image.width");
  expect_contains(error_of("[[object]]\ntype = \"sphere\"\nradius = -1\n"), "object[0].radius");
  expect_contains(error_of("[[object]]\ntype = \"sphere\"\ncenter = [0, inf, 0]\n"), "finite");
}

TEST(SceneParser, UnknownEnumValueListsChoices) {
  const std::string msg = error_of("[render]\nintegrator = \"pth\"\n");
  expect_contains(msg, "did you mean \"path\"");
  expect_contains(msg, "whitted");
}

TEST(SceneParser, MalformedToml) {
  const std::string msg = error_of("[image]\nwidth = = 3\n");
  expect_contains(msg, "test.toml:2");
  expect_contains(msg, "TOML syntax error");
}

TEST(SceneParser, MissingMeshFile) {
  const std::string msg = error_of("[[object]]\ntype = \"mesh\"\nfile = \"does_not_exist.obj\"\n");
  expect_contains(msg, "object[0].file");
  expect_contains(msg, "file not found");
}

TEST(SceneParser, UnknownMaterialSuggests) {
  const std::string msg = error_of(
      "[[material]]\nname = \"mirror\"\nreflectivity = 1\n[[object]]\ntype = \"sphere\"\nmaterial "
      "= \"miror\"\n");
  expect_contains(msg, "did you mean \"mirror\"");
}

TEST(SceneParser, EnergyConservationChecked) {
  expect_contains(error_of("[[material]]\nname = \"m\"\nreflectivity = 0.7\ntransmission = 0.6\n"),
                  "must not exceed 1");
}

TEST(SceneParser, SetOverridesAnyKey) {
  const Scene s =
      load_scene_from_string("[camera]\nfov = 60\n", "t.toml",
                             {"camera.fov=90", "image.width=320", "render.integrator=path"});
  EXPECT_NEAR(horizontal_fov_degrees(s), 90, 1e-9);
  EXPECT_EQ(s.render.width, 320);
  EXPECT_EQ(s.render.integrator, "path");
}

TEST(SceneParser, SetIntoArrayOfTables) {
  const Scene s = load_scene_from_string("[[object]]\ntype = \"sphere\"\nradius = 1\n", "t.toml",
                                         {"object.0.radius=2.5"});
  ASSERT_EQ(s.shapes.size(), 1u);
  EXPECT_DOUBLE_EQ(s.shapes[0].radius, 2.5);
  expect_contains(error_of("[[object]]\ntype = \"sphere\"\n", {"object.3.radius=2"}),
                  "not a valid index");
}

TEST(SceneParser, SetWithUnknownKeyIsAnError) {
  const std::string msg = error_of("", {"camera.fvo=90"});
  expect_contains(msg, "--set");
  expect_contains(msg, "did you mean 'fov'");
}

TEST(SceneParser, IncludesMergeTablesAndConcatenateArrays) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "anamorph_include_test";
  fs::create_directories(dir);
  std::ofstream(dir / "world.toml")
      << "[image]\nwidth = 100\nheight = 50\n[[object]]\ntype = \"sphere\"\n";
  std::ofstream(dir / "main.toml")
      << "include = \"world.toml\"\n[image]\nwidth = 200\n[[object]]\ntype = \"box\"\n";
  const Scene s = load_scene(dir / "main.toml");
  EXPECT_EQ(s.render.width, 200);  // the including file wins
  EXPECT_EQ(s.render.height, 50);  // the included file supplies the rest
  EXPECT_EQ(s.shapes.size(), 2u);  // arrays of tables concatenate
  std::ofstream(dir / "bad.toml") << "[image]\nwidht = 3\n";
  std::ofstream(dir / "main2.toml") << "include = \"bad.toml\"\n";
  try {
    load_scene(dir / "main2.toml");
    FAIL() << "expected an error";
  } catch (const SceneError& e) {
    expect_contains(e.what(), "bad.toml:2:1");  // errors point into the included file
  }
  // ... values' errors too (merged nodes are moved, keeping their source; a copy loses it and the
  // error used to say "--set").
  std::ofstream(dir / "bad2.toml") << "[image]\nwidth = -3\n";
  std::ofstream(dir / "main4.toml") << "include = \"bad2.toml\"\n";
  try {
    load_scene(dir / "main4.toml");
    FAIL() << "expected an error";
  } catch (const SceneError& e) {
    expect_contains(e.what(), "bad2.toml:2:9: image.width");
  }
  // Paths in an included file are relative to that file, wherever the including file is.
  fs::create_directories(dir / "sub" / "models");
  fs::copy_file(test::data_dir() / "models" / "shared_mesh.gltf",
                dir / "sub" / "models" / "m.gltf");
  std::ofstream(dir / "sub" / "world.toml")
      << "[[object]]\ntype = \"mesh\"\nfile = \"models/m.gltf\"\n";
  std::ofstream(dir / "main3.toml") << "include = \"sub/world.toml\"\n";
  EXPECT_EQ(load_scene(dir / "main3.toml").instances.size(), 2u);
  fs::remove_all(dir);
}

TEST(SceneParser, TransformComposesScaleRotateTranslate) {
  const Scene s = load_scene_from_string(
      "[[object]]\ntype = \"sphere\"\ntransform = { scale = 2, rotate = [90, 0, 1, 0], translate = "
      "[1, 0, 0] }\n",
      "t.toml");
  const Vec3 p = s.shapes[0].world_from_object.point({1, 0, 0});
  // scale: (2,0,0); rotate 90 about y: (0,0,-2); translate: (1,0,-2)
  EXPECT_NEAR(length(p - Vec3{1, 0, -2}), 0, 1e-12) << p.x << " " << p.y << " " << p.z;
}

TEST(SceneParser, OrgDirCompositionAndWarnings) {
  const Scene s = load_scene_from_string(
      "[camera]\norg = { type = \"point\", position = [0, 0, 0] }\ndir = { type = \"constant\", "
      "direction = [0, 0, -1] }\n",
      "t.toml");
  ASSERT_FALSE(s.warnings.empty());
  expect_contains(s.warnings[0], "same ray");
  expect_contains(error_of("[camera]\norg = { type = \"point\" }\n"), "dir");
  expect_contains(error_of("[camera]\npreset = \"perspective\"\norg = { type = \"point\" }\ndir = "
                           "{ type = \"constant\" }\n"),
                  "either a preset or org/dir");
}

}  // namespace anamorph

namespace anamorph {

TEST(SceneParser, SharedGltfMeshIsInstancedNotCopied) {
  const std::string file = (test::data_dir() / "models" / "shared_mesh.gltf").string();
  const Scene s = load_scene_from_string("[[object]]\ntype = \"mesh\"\nfile = \"" + file +
                                             "\"\ntransform = { translate = [10, 0, 0] }\n",
                                         "t.toml");
  EXPECT_EQ(s.prototypes.size(), 1u);
  ASSERT_EQ(s.instances.size(), 2u);
  // The object transform applies on top of each node's.
  const Vec3 o = s.instances[0].world_from_object.point({0, 0, 0});
  EXPECT_GE(o.x, 9.0) << o.x;
}

TEST(SceneParser, GltfCameraSelectable) {
  ANAMORPH_REQUIRE_SHARED();
  const std::string file = (test::shared_scenes() / "gltf" / "Cameras" / "Cameras.gltf").string();
  const std::string base =
      "[image]\nwidth = 100\nheight = 100\n[[object]]\ntype = \"mesh\"\nfile = \"" + file + "\"\n";
  const Scene s = load_scene_from_string(base + "[camera]\ngltf_camera = 0\n", "t.toml");
  EXPECT_NE(s.camera->describe().find("glTF perspective"), std::string::npos)
      << s.camera->describe();
  // yfov 0.7 rad with aspect 1: the vertical edge-to-edge angle is 0.7 rad.
  const auto top = s.camera->generate({{0.5, 0.0}}), bottom = s.camera->generate({{0.5, 1.0}});
  EXPECT_NEAR(std::acos(dot(top->dir, bottom->dir)), 0.7, 1e-9);
  const Scene o = load_scene_from_string(base + "[camera]\ngltf_camera = 1\n", "t.toml");
  EXPECT_NE(o.camera->describe().find("orthographic"), std::string::npos);
  try {
    load_scene_from_string(base + "[camera]\ngltf_camera = 5\n", "t.toml");
    FAIL() << "camera 5 does not exist";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("there are 2 cameras"), std::string::npos) << e.what();
  }
}

TEST(SceneParser, ThreeBoxTexturedContainersRenderAlike) {
  ANAMORPH_REQUIRE_SHARED();
  const auto g = test::shared_scenes() / "gltf";
  size_t tris = 0;
  for (const auto& f : {g / "BoxTextured-glTF" / "BoxTextured.gltf",
                        g / "BoxTextured-glTF-Binary" / "BoxTextured.glb",
                        g / "BoxTextured-glTF-Embedded" / "BoxTextured.gltf"}) {
    const Scene s = load_scene_from_string(
        "[[object]]\ntype = \"mesh\"\nfile = \"" + f.string() + "\"\n", "t.toml");
    EXPECT_EQ(s.instanced_triangle_count(), 12u) << f;
    tris += s.triangle_count();
  }
  EXPECT_EQ(tris, 36u);
}

}  // namespace anamorph
