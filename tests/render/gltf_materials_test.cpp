// glTF material extensions rendered against values known in closed form: a quad in front of an
// unlit white wall, seen head-on by the path tracer in a black world (issue 34, part 3).
//   KHR_materials_unlit        the pixel is the base colour
//   alphaMode BLEND            the wall shows through by 1 - alpha
//   KHR_materials_transmission thin (no volume): the wall shows through by 1 - Fresnel
#include <gtest/gtest.h>

#include <string>

#include <nlohmann/json.hpp>

#include "render_util.h"
#include "scene/loader_fixture.h"

namespace anamorph {
namespace {

using Json = nlohmann::json;

// The wall (z = -2, unlit white) and a front quad (z = -1) of material `front`, both 20 m wide.
std::filesystem::path write_scene(const test::ScratchDir& dir, const Json& front,
                                  const Json& extensions) {
  test::GltfWriter w;
  const auto quad = [&](float z) {
    return w.floats({-10, -10, z, 10, -10, z, 10, 10, z, -10, 10, z}, "VEC3");
  };
  const int idx = w.indices(std::vector<uint16_t>{0, 1, 2, 0, 2, 3});
  w.j["materials"] = {{{"name", "wall"},
                       {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}}},
                       {"extensions", {{"KHR_materials_unlit", Json::object()}}}},
                      front};
  w.j["extensionsUsed"] = extensions;
  w.node({{"mesh", w.mesh({{"POSITION", quad(-2)}}, idx, 0, 4, "wall")}});
  w.node({{"mesh", w.mesh({{"POSITION", quad(-1)}}, idx, 1, 4, "front")}});
  return dir.write("front.gltf", w.text());
}

Color mean_through(const Json& front, const Json& extensions) {
  const test::ScratchDir dir;
  const auto file = write_scene(dir, front, extensions);
  const test::Rendered r = test::render_text(
      "[image]\nwidth = 16\nheight = 16\n[render]\nintegrator = \"path\"\nspp = 64\nmax_depth = "
      "9\n[camera]\nfov = 20\nlook_from = [0, 0, 0]\nlook_at = [0, 0, -1]\n[[object]]\ntype = "
      "\"mesh\"\nfile = \"" +
      file.string() + "\"\n");
  Color sum{0, 0, 0};
  for (int y = 0; y < 16; ++y)
    for (int x = 0; x < 16; ++x) sum += r.film->pixel(x, y);
  return sum / 256.0;
}

TEST(GltfExtensionRender, UnlitShowsItsBaseColour) {
  const Json front = {{"name", "flat"},
                      {"pbrMetallicRoughness", {{"baseColorFactor", {0.2, 0.4, 0.6, 1}}}},
                      {"extensions", {{"KHR_materials_unlit", Json::object()}}}};
  const Color c = mean_through(front, {"KHR_materials_unlit"});
  EXPECT_NEAR(c.x, 0.2, 1e-6);
  EXPECT_NEAR(c.y, 0.4, 1e-6);
  EXPECT_NEAR(c.z, 0.6, 1e-6);
}

// A black quad of alpha 0.25: 3/4 of the white wall (its 4 % Fresnel reflection sees only the
// black world). Per-sample choice: 64 x 256 samples, each 0 or 1: standard error 0.0034.
TEST(GltfExtensionRender, AlphaBlendIsTransparency) {
  const Json front = {
      {"name", "veil"},
      {"alphaMode", "BLEND"},
      {"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 0.25}}, {"metallicFactor", 0}}}};
  const Color c = mean_through(front, {"KHR_materials_unlit"});
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(c[k], 0.75, 0.015) << "channel " << k;
}

// A thin wall (transmission 1, no KHR_materials_volume), white, ior 1.5: the wall behind shows
// through by 1 - F, F = 0.04 head-on (0.0401 at the image's corners, 14 degrees off axis).
TEST(GltfExtensionRender, ThinTransmissionPassesOneMinusFresnel) {
  const Json front = {
      {"name", "pane"},
      {"pbrMetallicRoughness",
       {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 0}}},
      {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 1}}}}}};
  const Color c = mean_through(front, {"KHR_materials_unlit", "KHR_materials_transmission"});
  // Reflect with probability F (then black), else through: 64 x 256 Bernoulli(0.96) samples,
  // standard error 0.0015.
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(c[k], 0.96, 0.006) << "channel " << k;
}

}  // namespace
}  // namespace anamorph
