// The seam of docs/architecture.md's "How to add a material", walked by a test: this file alone
// defines a material kind (`test_grey`: its class, its key, its registry entry) and adds it to the
// registry; nothing else in the repository names it. The scene reader, its checks and messages,
// the docs, the JSON Schema, `anamorph info`'s description and both integrators then take it as
// they take the built-in kinds.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "material/material_kinds.h"
#include "render_util.h"
#include "scene/scene_schema.h"

namespace anamorph {

namespace {

// `test_grey`: a Lambert surface reflecting `albedo` times its colour.
class GreyMaterial final : public Material {
 public:
  static constexpr std::string_view kType = "test_grey";
  double albedo = 0.5;

  std::string_view type() const override { return kType; }
  std::string describe() const override { return fmt::format("{}, albedo {}", kType, albedo); }
  Bsdf bsdf(const ShadingPoint& sp, const Vec3& wo) const override {
    Bsdf b = bsdf_frame(sp, wo);
    b.diffuse = base_color.eval(sp.tex) * albedo;
    return b;
  }
  Color diffuse_reflectance() const override { return base_color.value * albedo; }
  double shadow_transmission() const override { return 0; }
  bool spawns_specular_rays() const override { return false; }
};

const ParamSpec kGreyParams[] = {
    {"albedo", ParamType::Number, "0.5", "Reflectance (times `color`).", 0, 1},
};

std::unique_ptr<Material> create_grey(const ParamValues& v) {
  auto m = std::make_unique<GreyMaterial>();
  m->albedo = v.number("albedo");
  return m;
}

const MaterialKind kGreyKind{GreyMaterial::kType, "A test's Lambert surface.", kGreyParams,
                             create_grey};
// (Registered while static objects are initialized, before anything reads the kinds.)
const bool kGreyAdded = add_material_kind(kGreyKind);

// One pixel at the center of a sphere of material `m` under a uniform sky of radiance 1.
std::string grey_scene(const std::string& integrator, const std::string& material_keys) {
  return "[image]\nwidth = 1\nheight = 1\n[render]\nsampler = \"center\"\nintegrator = \"" +
         integrator +
         "\"\n"
         "[camera]\nlook_from = [0, 0, 5]\nlook_at = [0, 0, 0]\nfov = 10\n"
         "[[material]]\nname = \"m\"\ntype = \"test_grey\"\n" +
         material_keys +
         "[[object]]\ntype = \"sphere\"\nradius = 1\nmaterial = \"m\"\n"
         "[environment]\ncolor = 1\n";
}

std::string load_error(const std::string& scene) {
  try {
    load_scene_from_string(scene, "test.toml");
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(loaded)";
}

}  // namespace

TEST(MaterialKind, AddedKindIsReadAndDescribed) {
  ASSERT_TRUE(kGreyAdded);
  const Scene s = load_scene_from_string(grey_scene("whitted", "albedo = 0.25\n"), "test.toml");
  ASSERT_EQ(s.materials.size(), 2u);  // (the default material, then "m")
  EXPECT_EQ(s.materials[1]->type(), "test_grey");
  EXPECT_EQ(s.materials[1]->describe(), "test_grey, albedo 0.25");
  EXPECT_EQ(s.materials[1]->diffuse_reflectance(), Color(0.8 * 0.25))
      << "colour 0.8 (the default) x albedo 0.25";
}

TEST(MaterialKind, AddedKindsKeysAreCheckedAsAnyOthers) {
  const std::string range = load_error(grey_scene("whitted", "albedo = 2\n"));
  EXPECT_NE(range.find("albedo"), std::string::npos) << range;
  EXPECT_NE(range.find("out of range"), std::string::npos) << range;
  const std::string unknown = load_error(grey_scene("whitted", "albedoo = 0.2\n"));
  EXPECT_NE(unknown.find("albedo"), std::string::npos) << "suggests the key: " << unknown;
  // Another kind's key is not this kind's.
  const std::string other = load_error(grey_scene("whitted", "reflectivity = 1\n"));
  EXPECT_NE(other.find("reflectivity"), std::string::npos) << other;
  // The valid types listed on a typo include it.
  const std::string type = load_error(
      "[[material]]\nname = \"m\"\ntype = \"test_gray\"\n[[object]]\ntype = \"sphere\"\n");
  EXPECT_NE(type.find("test_grey"), std::string::npos) << type;
}

TEST(MaterialKind, AddedKindIsInTheDocsAndTheJsonSchema) {
  const std::string docs = scene_doc_block("material");
  EXPECT_NE(docs.find("#### `type = \"test_grey\"`"), std::string::npos) << docs;
  EXPECT_NE(docs.find("`albedo`"), std::string::npos) << docs;
  EXPECT_NE(scene_json_schema().find("\"test_grey\""), std::string::npos);
}

TEST(MaterialKind, WhittedShowsItsAmbientTermExactly) {
  // Whitted's ambient term: the diffuse part times the environment's mean, unshadowed.
  const auto r = test::render_text(grey_scene("whitted", "color = 0.5\nalbedo = 0.5\n"));
  EXPECT_EQ(r.film->pixel(0, 0), Color(0.25)) << "0.5 x 0.5 x radiance 1";
}

TEST(MaterialKind, PathTracedFurnaceReflectsItsAlbedo) {
  // A convex Lambert surface under radiance 1 everywhere reflects its albedo exactly, in the
  // mean: 8 x 8 pixels at 16 samples each stay within 0.02 of it.
  const auto r = test::render_text(grey_scene("path", "albedo = 0.6\n"),
                                   {"image.width=8", "image.height=8", "render.spp=16",
                                    "render.sampler=\"stratified\"", "camera.fov=8"});
  double sum = 0;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) sum += luminance(r.film->pixel(x, y));
  EXPECT_NEAR(sum / 64, 0.8 * 0.6, 0.02) << "colour 0.8 (the default) x albedo 0.6";
}

}  // namespace anamorph
