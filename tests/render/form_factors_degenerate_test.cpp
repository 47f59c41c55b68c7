// Form factors and radiosity for degenerate inputs (issue 32's second probe): tiny objects,
// objects too small or too shrunk for double precision, names that collide with each other or
// with the environment column, reflectances outside [0, 1] from a model, textured materials and
// lossless enclosures. Every result is finite, every refusal says why, nothing is dropped
// silently.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "accel/accel.h"
#include "render/form_factors.h"
#include "render/radiosity.h"
#include "scene/scene_loader.h"
#include "test_util.h"

namespace anamorph {
namespace {

namespace fs = std::filesystem;

struct Measured {
  Scene scene;
  std::unique_ptr<Accel> accel;
  FormFactors f;
};

Measured measure(const std::string& toml, FormFactorOptions o = {}) {
  Measured m{load_scene_from_string(toml, "degenerate_test.toml"), nullptr, {}};
  m.accel = std::make_unique<Accel>(m.scene);
  m.f = measure_form_factors(*m.accel, o);
  return m;
}

FormFactorOptions options(int origins, int rays, std::vector<std::string> inward = {}) {
  FormFactorOptions o;
  o.origins = origins, o.rays = rays, o.inward = std::move(inward);
  return o;
}

bool all_finite(const FormFactors& f) {
  for (size_t r = 0; r < f.rows.size(); ++r) {
    if (!std::isfinite(f.areas[size_t(f.rows[r])])) return false;
    for (size_t c = 0; c < f.F[r].size(); ++c)
      if (!std::isfinite(f.F[r][c]) || !std::isfinite(f.error[r][c])) return false;
  }
  return std::isfinite(f.worst_reciprocity_z);
}

// A lamp sphere (Le = 1, reflectance 0.5) of radius `r` inside an inward dome (reflectance 0.6).
std::string lamp_in_dome(const std::string& r, const std::string& extra = "") {
  return "[[material]]\nname = \"lamp\"\ncolor = 0.5\nemission = 1\n[[material]]\nname = "
         "\"wall\"\ncolor = 0.6\n[[object]]\ntype = \"sphere\"\nname = \"lamp\"\nradius = " +
         r + "\nmaterial = \"lamp\"\n" + extra +
         "[[object]]\ntype = \"sphere\"\nname = \"dome\"\nradius = 2\nmaterial = \"wall\"\n";
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "<accepted>";
}

TEST(DegenerateFormFactors, TinyObjectsGiveFiniteFormFactorsAndRadiosity) {
  // (Radius 1e-100: area 1.26e-199, whose squared weights underflowed to NaN before.)
  for (const char* r : {"1e-100", "1e-150"}) {
    const Measured m = measure(lamp_in_dome(r), options(64, 64, {"dome"}));
    ASSERT_EQ(m.f.rows.size(), 2u) << r;
    EXPECT_TRUE(all_finite(m.f)) << r;
    const double radius = std::stod(r), area = 4 * kPi * radius * radius;
    EXPECT_NEAR(m.f.areas[0] / area, 1, 1e-12) << r << ": area " << m.f.areas[0];
    EXPECT_EQ(m.f.F[0][1], 1) << "the lamp sees only the dome";
    const std::vector<Color> B = solve_radiosity(m.scene, *m.accel, m.f);
    const PathRadiance p =
        path_traced_radiance(m.scene, *m.accel, m.f, options(64, 64, {"dome"}), 16);
    // The lamp's radiosity is its own emission (pi Le); the dome receives a negligible share.
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(B[0][c] / kPi, 1, 1e-9) << r;
      EXPECT_NEAR(B[1][c], 0, 1e-12) << r;
      EXPECT_TRUE(std::isfinite(p.mean[0][c]) && std::isfinite(p.error[0][c])) << r;
      EXPECT_NEAR(p.mean[0][c], 1, 1e-9) << r << ": the path tracer's lamp";
    }
  }
}

TEST(DegenerateFormFactors, ObjectsBeyondDoublePrecisionHaveNoRowAndSayWhy) {
  const struct {
    std::string toml, why;
  } cases[] = {
      {lamp_in_dome("1e-200"), "its surface area underflows to 0 (too small for double precision)"},
      {lamp_in_dome("1", "transform = { scale = 1e-200 }\n"),
       "its transform makes its surface area underflow (too small for double precision)"},
  };
  for (const auto& c : cases) {
    const Measured m = measure(c.toml, options(16, 16, {"dome"}));
    ASSERT_EQ(m.f.no_row.size(), 2u);
    EXPECT_EQ(m.f.no_row[0], c.why);
    EXPECT_EQ(m.f.no_row[1], "");
    EXPECT_EQ(m.f.rows, std::vector<int>{1});
    EXPECT_TRUE(all_finite(m.f));
    // Asked for by name, or needed by radiosity: an error that says why.
    FormFactorOptions lamp = options(16, 16, {"dome"});
    lamp.sources = {"lamp"};
    EXPECT_EQ(error_of([&] { measure(c.toml, lamp); }),
              "'lamp' has no row of form factors: " + c.why);
    EXPECT_EQ(error_of([&] { check_radiosity_inputs(m.scene, *m.accel, {"dome"}); }),
              "radiosity needs a row of form factors for every object, and 'lamp' can have none: " +
                  c.why);
  }
  // An infinite plane is a receiver only, and says so.
  const Measured plane = measure(
      "[[object]]\ntype = \"plane\"\nname = \"floor\"\n" + lamp_in_dome("0.5"), options(16, 16));
  EXPECT_EQ(plane.f.no_row[0], "an infinite plane has no finite area");
}

TEST(DegenerateFormFactors, NamesAreUniqueAndTheEnvironmentColumnIsNotAnObjectName) {
  const std::string sphere = "[[object]]\ntype = \"sphere\"\nradius = 0.1\nname = ";
  const Measured m = measure(sphere + "\"environment\"\n" + sphere +
                                 "\"lamp\"\ntransform = { translate = [1, 0, 0] }\n" + sphere +
                                 "\"lamp\"\ntransform = { translate = [2, 0, 0] }\n" + sphere +
                                 "\"lamp#2\"\ntransform = { translate = [3, 0, 0] }\n",
                             options(8, 16));
  EXPECT_EQ(m.f.names, (std::vector<std::string>{"environment#2", "lamp", "lamp#3", "lamp#2"}));
  ASSERT_EQ(m.f.notes.size(), 1u);
  EXPECT_EQ(m.f.notes[0],
            "the object named 'environment' is listed as 'environment#2': 'environment' names the "
            "column of rays that hit nothing");
}

TEST(DegenerateFormFactors, RadiosityRefusesWhatItCannotSolveBeforeMeasuring) {
  // A model whose material reflects 2.5 times the light (glTF's baseColorFactor has no range
  // check in the scene reader: it comes from the file).
  const fs::path dir = fs::temp_directory_path() / ("anamorph_ff_" + std::to_string(getpid()));
  fs::create_directories(dir);
  std::ifstream in(test::data_dir() / "models" / "shared_mesh.gltf");
  std::stringstream text;
  text << in.rdbuf();
  std::string gltf = text.str();
  const size_t at = gltf.find("0.5,");
  ASSERT_NE(at, std::string::npos);
  gltf.replace(at, 4, "2.5,");
  std::ofstream(dir / "bright.gltf") << gltf;
  const std::string model = "[[object]]\ntype = \"mesh\"\nname = \"model\"\nfile = \"" +
                            (dir / "bright.gltf").string() + "\"\n";
  const struct {
    std::string toml, want;
  } cases[] = {
      {model,
       "(material 'grey') reflects 2.5 of the light in the red channel: radiosity needs a "
       "reflectance within [0, 1]"},
      {lamp_in_dome("0.5").replace(lamp_in_dome("0.5").find("color = 0.6"), 11,
                                   "color = { type = \"checker\" }"),
       "radiosity needs one colour per object, and 'dome' (material 'wall') has a textured colour"},
  };
  for (const auto& c : cases) {
    const Scene s = load_scene_from_string(c.toml, "degenerate_test.toml");
    const Accel accel(s);
    const std::string got = error_of([&] { check_radiosity_inputs(s, accel, {"dome"}); });
    EXPECT_NE(got.find(c.want), std::string::npos) << "got: " << got << "\nwanted: " << c.want;
  }
  fs::remove_all(dir);
  // Everything reflects all light inside a closed dome: no steady state, said so (was: B of
  // 1e15 or NaN). With one absorbing object it solves, finite and non-negative.
  std::string lossless = lamp_in_dome("0.5");
  for (const char* from : {"color = 0.5", "color = 0.6"})
    lossless.replace(lossless.find(from), 11, "color = 1.0");
  const Measured closed = measure(lossless, options(64, 16, {"dome"}));
  EXPECT_EQ(error_of([&] { solve_radiosity(closed.scene, *closed.accel, closed.f); }),
            "the radiosity system (I - rho F) B = E has no solution in the red channel: 'lamp', "
            "'dome' reflect all light (reflectance 1) and see only each other, so light is never "
            "absorbed and there is no steady state: give one of them a reflectance below 1");
  std::string absorbing = lossless;
  absorbing.replace(absorbing.find("color = 1.0"), 11, "color = 0.9");
  const Measured open = measure(absorbing, options(64, 16, {"dome"}));
  const std::vector<Color> B = solve_radiosity(open.scene, *open.accel, open.f);
  for (const Color& b : B) EXPECT_TRUE(is_finite(b) && min_component(b) >= 0) << b.x;
}

}  // namespace
}  // namespace anamorph
