// Invalid definitions throw ParamError naming the offending key (the scene parser turns the key
// into a file position).
#include <gtest/gtest.h>

#include <string>

#include "camera/functions.h"
#include "scene/scene_loader.h"
#include "scene/toml_reader.h"

namespace anamorph {
namespace {

struct Bad {
  const char* kind;  // "org" or "dir"
  const char* type;
  const char* toml;
  const char* key;   // expected ParamError::key
  const char* what;  // label
};

void PrintTo(const Bad& b, std::ostream* os) { *os << b.what; }

#define NET3x3 \
  "points = [[[0,0,0],[1,0,0],[2,0,0]],[[0,1,0],[1,1,1],[2,1,0]],[[0,2,0],[1,2,0],[2,2,0]]]\n"
#define NET4x4                                                                     \
  "points = [[[0,0,0],[1,0,0],[2,0,0],[3,0,0]],[[0,1,0],[1,1,1],[2,1,0],[3,1,0]]," \
  "[[0,2,0],[1,2,0],[2,2,1],[3,2,0]],[[0,3,0],[1,3,0],[2,3,0],[3,3,0]]]\n"

const Bad kBad[] = {
    // splines
    {"org", "bspline", NET4x4 "knots_u = [0, 0, 0, 1, 1, 1]", "knots_u", "knot vector too short"},
    {"org", "bspline", NET4x4 "knots_v = [0, 0, 0, 0, 0.6, 0.5, 1, 1, 1]", "knots_v",
     "knot vector decreasing"},
    {"org", "bspline", NET4x4 "degree_u = 1\nknots_u = [0, 0, 0.5, 0.5, 1, 1]", "knots_u",
     "interior knot repeated beyond the degree"},
    {"org", "bspline", NET3x3, "degree_u", "degree >= number of control points"},
    {"org", "bspline", NET4x4 "degree_v = 4", "degree_v", "degree_v >= number of rows"},
    {"org", "bspline", NET4x4 "degree_u = 16", "degree_u", "degree above the cap"},
    {"org", "bspline", NET4x4 "degree_u = 0", "degree_u", "degree zero"},
    {"org", "bspline", "points = [[[0,0,0],[1,0,0]],[[0,1,0]]]\ndegree_u = 1\ndegree_v = 1",
     "points", "ragged rows"},
    {"org", "bspline", "points = [[[0,0,0],[1,0,0]]]\ndegree_u = 1\ndegree_v = 1", "points",
     "a single row"},
    {"org", "bspline", NET4x4 "knot_type_u = \"periodic\"", "knot_type_u", "unknown knot type"},
    {"org", "bspline", NET4x4 "u_range = [0, 1.5]", "u_range", "range beyond the domain"},
    {"org", "nurbs", NET3x3 "degree_u = 2\ndegree_v = 2\nweights = [[1,1,1],[1,0,1],[1,1,1]]",
     "weights", "zero weight"},
    {"org", "nurbs", NET3x3 "degree_u = 2\ndegree_v = 2\nweights = [[1,1,1],[1,-2,1],[1,1,1]]",
     "weights", "negative weight"},
    {"org", "nurbs", NET3x3 "degree_u = 2\ndegree_v = 2\nweights = [[1,1,1],[1,1,1]]", "weights",
     "weights with too few rows"},
    {"org", "nurbs", NET3x3 "degree_u = 2\ndegree_v = 2\nweights = [[1,1,1],[1,1],[1,1,1]]",
     "weights", "ragged weights"},
    {"org", "nurbs", NET3x3 "degree_u = 2\ndegree_v = 2", "weights", "nurbs without weights"},
    {"org", "bezier", "points = []", "points", "empty net"},
    // analytic surfaces
    {"org", "sphere", "radius = -1", "radius", "negative radius"},
    {"org", "sphere", "radius = 0", "radius", "zero radius"},
    {"org", "sphere", "axis = [0, 0, 0]", "axis", "zero axis"},
    {"org", "sphere", "axis = [0, 1, 0]\nfront = [0, 2, 0]", "front", "front along the axis"},
    {"org", "sphere", "u_range = [10, 10]", "u_range", "empty range"},
    {"org", "sphere", "colour = 3", "colour", "unknown key"},
    {"org", "cylinder", "axis = [0, 0, 0]", "axis", "zero cylinder axis"},
    {"org", "cylinder", "radius = -2", "radius", "negative cylinder radius"},
    {"org", "cone", "half_angle = 90", "half_angle", "flat cone"},
    {"org", "cone", "v_range = [1, -1]", "v_range", "cone through its apex"},
    {"org", "torus", "minor_radius = -0.1", "minor_radius", "negative minor radius"},
    {"org", "torus", "major_radius = 0", "major_radius", "zero major radius"},
    {"org", "ellipsoid", "radii = [1, 0, 1]", "radii", "zero semi-axis"},
    {"org", "quadric", "matrix = [[1, 0, 0], [0, 1, 0], [1, 1, 0]]", "matrix", "singular matrix"},
    {"org", "quadric", "matrix = [[1, 0, 0], [0, 1, 0]]", "matrix", "two rows"},
    {"org", "quadric", "kind = \"cube\"", "kind", "unknown kind"},
    {"org", "superquadric", "exponent_ns = 0", "exponent_ns", "zero exponent"},
    {"org", "superquadric", "exponent_ew = 2.5", "exponent_ew", "exponent above 2"},
    {"org", "plane", "edge_u = [1, 0, 0]\nedge_v = [2, 0, 0]", "edge_u", "parallel edges"},
    {"org", "plane", "size = [1, -1]", "size", "negative size"},
    {"org", "plane", "size = [1, 1]\nnormal = [0, 1, 0]\nup = [0, 2, 0]", "up",
     "up along the normal"},
    {"org", "plane", "size = [1, 1]\nnormal = [0, 0, 0]", "normal", "zero normal"},
    {"org", "point", "position = [0, nan, 0]", "position", "not a number"},
    {"org", "mesh", "file = \"/nonexistent/anamorph/missing.obj\"", "file", "missing mesh file"},
    {"org", "mesh", "", "file", "mesh without file"},
    {"org", "expression", "x = \"u\"\ny = \"v\"\nz = \"sin(\"", "z", "formula syntax error"},
    // directions
    {"dir", "constant", "direction = [0, 0, 0]", "direction", "zero direction"},
    {"dir", "from_surface", "", "surface", "from_surface without surface"},
    {"dir", "from_surface", "surface = { type = \"sphere\", radius = -1 }", "surface.radius",
     "nested error"},
    {"dir", "from_surface", "surface = { type = \"sphear\" }", "surface", "unknown nested type"},
    {"dir", "from_surface", "surface = { type = \"sphere\", radiuss = 1 }", "surface.radiuss",
     "unknown nested key"},
    {"dir", "deviated_normal", "angle = 200", "angle", "angle above 180"},
    {"dir", "normal", "flip = 1", "flip", "wrong type"},
    {"dir", "expression", "x = \"nx\"\ny = \"ny\"\nz = \"nz + t\"", "z", "unknown variable"},
};

class FunctionErrorTest : public ::testing::TestWithParam<Bad> {};

TEST_P(FunctionErrorTest, ThrowsParamErrorNamingTheKey) {
  const Bad& b = GetParam();
  try {
    if (std::string(b.kind) == "org")
      make_org(b.type, b.toml);
    else
      make_dir(b.type, b.toml);
    FAIL() << b.what << ": accepted " << b.type << " { " << b.toml << " }";
  } catch (const ParamError& e) {
    EXPECT_EQ(e.key, b.key) << b.what << ": " << e.what();
    EXPECT_FALSE(std::string(e.what()).empty());
  }
}

INSTANTIATE_TEST_SUITE_P(All, FunctionErrorTest, ::testing::ValuesIn(kBad), [](const auto& p) {
  std::string n = p.param.what;
  for (char& c : n)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return n;
});

TEST(FunctionErrors, UnknownTypesListTheValidNames) {
  try {
    make_org("spehre");
    FAIL();
  } catch (const ParamError& e) {
    EXPECT_EQ(e.key, "type");
    EXPECT_NE(std::string(e.what()).find("sphere"), std::string::npos) << e.what();
  }
  try {
    make_dir("norml");
    FAIL();
  } catch (const ParamError& e) {
    EXPECT_NE(std::string(e.what()).find("normal"), std::string::npos) << e.what();
  }
}

TEST(FunctionErrors, ProgrammaticValuesAreCheckedLikeParsedOnes) {
  // A preset building ParamValues in code gets the same range checks as a scene file.
  ParamValues v = params_from_toml(find_org_function("sphere")->params, "");
  v.set("radius", -2.0);
  try {
    find_org_function("sphere")->create(v);
    FAIL();
  } catch (const ParamError& e) {
    EXPECT_EQ(e.key, "radius");
  }
  v.set("radius", int64_t(2));  // an integer where a number is declared
  EXPECT_THROW(find_org_function("sphere")->create(v), ParamError);
}

}  // namespace
// The registry (make_org from TOML text) and the scene parser convert values with the same code
// (param_toml.h), so a bad value gets the same words from both; the scene adds where it is.
TEST(ParamConversion, RegistryAndSceneParserSayTheSame) {
  const std::string bad[] = {"radius = \"big\"", "radius = -1", "u_range = [0, 1, 2]"};
  for (const std::string& b : bad) {
    std::string registry, scene;
    try {
      make_org("sphere", b);
    } catch (const ParamError& e) {
      registry = e.what();
    }
    try {
      load_scene_from_string(
          "[camera]\ndir = { type = \"normal\" }\n[camera.org]\ntype = "
          "\"sphere\"\n" +
              b + "\n",
          "t.toml");
    } catch (const SceneError& e) {
      scene = e.what();
    }
    ASSERT_FALSE(registry.empty()) << b;
    ASSERT_FALSE(scene.empty()) << b;
    // registry: "radius: <message>"; scene: "t.toml:L:C: camera.org.radius: <message>".
    const std::string message = registry.substr(registry.find(": ") + 2);
    EXPECT_TRUE(scene.ends_with(": " + message))
        << b << "\nregistry: " << registry << "\nscene:    " << scene;
  }
}

}  // namespace anamorph
