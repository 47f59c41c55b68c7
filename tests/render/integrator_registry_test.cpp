// The integrators by name (render/integrators.cpp) and the names the scene reader declares
// (scene/scene_schema.cpp) are one list; the views are not integrators; an unknown name is an
// error that lists the valid ones, at load and in make_integrator (never a fallback).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "accel/accel.h"
#include "render/integrator.h"
#include "render/lights.h"
#include "scene/scene_loader.h"
#include "scene/scene_schema.h"

namespace anamorph {

namespace {

std::string load_error(const std::string& scene) {
  try {
    load_scene_from_string(scene, "test.toml");
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(loaded)";
}

}  // namespace

TEST(IntegratorRegistry, MakesExactlyTheDeclaredIntegrators) {
  std::vector<std::string> made, declared;
  for (const IntegratorFactory* f : integrator_factories()) made.emplace_back(f->name);
  for (const IntegratorDecl& d : declared_integrators()) declared.emplace_back(d.name);
  EXPECT_EQ(made, declared) << "render/integrators.cpp's list and scene_schema.cpp's declarations";
}

TEST(IntegratorRegistry, EveryChoiceIsAnIntegratorOrAView) {
  size_t integrators = 0, views = 0;
  for (const std::string_view name : integrator_names()) {
    RenderSettings rs;
    rs.integrator = "path";
    ASSERT_TRUE(select_integrator(rs, name)) << name;
    EXPECT_EQ(rs.shown(), name);
    if (rs.view == View::Beauty) {
      ++integrators;
      EXPECT_EQ(rs.integrator, name);
    } else {
      ++views;
      EXPECT_EQ(name_of(rs.view), name);
      EXPECT_EQ(rs.integrator, "path") << "a view keeps the integrator: " << name;
      EXPECT_FALSE(rs.deterministic()) << name;
      EXPECT_FALSE(rs.adaptive()) << name;
    }
  }
  EXPECT_EQ(integrators, declared_integrators().size());
  EXPECT_EQ(views, size_t(View::Uv)) << "every View but Beauty has its name";
  RenderSettings rs;
  EXPECT_FALSE(select_integrator(rs, "whited"));
  EXPECT_EQ(rs.integrator, "whitted");
}

TEST(IntegratorRegistry, UnknownNameIsALoadErrorListingTheValidOnes) {
  const std::string e = load_error("[render]\nintegrator = \"whited\"\n");
  for (const char* want : {"test.toml:2", "integrator", "\"whitted\"", "\"path\"", "\"albedo\""})
    EXPECT_NE(e.find(want), std::string::npos) << want << " in: " << e;
}

TEST(IntegratorRegistry, MakeIntegratorRefusesAnUnknownName) {
  const Scene scene = load_scene_from_string("[image]\nwidth = 1\nheight = 1\n", "test.toml");
  const Accel accel(scene);
  const Lights lights(scene, accel);
  const RenderContext ctx{scene, accel, lights, 5};
  for (const IntegratorFactory* f : integrator_factories())
    EXPECT_NE(make_integrator(f->name, ctx), nullptr) << f->name;
  try {
    make_integrator("albedo", ctx);  // (a view, not an integrator)
    FAIL() << "made an integrator named albedo";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("valid: whitted, path"), std::string::npos) << e.what();
  }
}

TEST(IntegratorRegistry, LatticeIsRefusedForANoisyIntegratorOnly) {
  const std::string path = load_error("[render]\nintegrator = \"path\"\nantialias = \"lattice\"\n");
  EXPECT_NE(path.find("`path`"), std::string::npos) << path;
  EXPECT_EQ(load_error("[render]\nintegrator = \"albedo\"\nantialias = \"lattice\"\n"), "(loaded)");
  EXPECT_EQ(load_error("[render]\nintegrator = \"whitted\"\nantialias = \"lattice\"\n"),
            "(loaded)");
}

}  // namespace anamorph
