// Form factors from the hemispherical virtual camera against closed forms (within 3 standard
// errors), conservation in a closed room, reciprocity, determinism, and the radiosity solution
// against the analytic one and the path tracer.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "accel/accel.h"
#include "render/form_factors.h"
#include "render/radiosity.h"
#include "scene/scene_loader.h"

namespace anamorph {
namespace {

struct Measured {
  Scene scene;
  std::unique_ptr<Accel> accel;
  FormFactors f;
};

Measured measure(const std::string& toml, FormFactorOptions o = {}) {
  Measured m{load_scene_from_string(toml, "form_factors_test.toml"), nullptr, {}};
  m.accel = std::make_unique<Accel>(m.scene);
  m.f = measure_form_factors(*m.accel, o);
  return m;
}

int column(const FormFactors& f, const std::string& name) {
  for (size_t i = 0; i < f.names.size(); ++i)
    if (f.names[i] == name) return int(i);
  return int(f.names.size());  // the environment
}
int row(const FormFactors& f, const std::string& name) {
  const int c = column(f, name);
  for (size_t r = 0; r < f.rows.size(); ++r)
    if (f.rows[r] == c) return int(r);
  ADD_FAILURE() << "no row for " << name;
  return 0;
}

// F(from -> to) equals `exact` within 3 standard errors (and the error is small).
void expect_form_factor(const FormFactors& f, const std::string& from, const std::string& to,
                        double exact) {
  const int r = row(f, from), c = column(f, to);
  const double got = f.F[size_t(r)][size_t(c)], se = f.error[size_t(r)][size_t(c)];
  EXPECT_LE(std::abs(got - exact), 3 * se)
      << from << " -> " << to << ": measured " << got << " +- " << se << ", exact " << exact << " ("
      << std::abs(got - exact) / se << " standard errors)";
  EXPECT_LT(se, 0.01 * std::max(exact, 0.05)) << from << " -> " << to;
}

const char* kPointFacingDisc = R"(
[[object]]
type = "disk"
name = "point"
radius = 0.001
[[object]]
type = "disk"
name = "disc"
radius = 1.5
transform = { translate = [0, 2, 0] }
)";

TEST(FormFactors, PointFacingACoaxialDisc) {
  // F = R^2 / (R^2 + H^2) (a differential area facing a coaxial disc).
  FormFactorOptions o;
  o.sources = {"point"};
  const Measured m = measure(kPointFacingDisc, o);
  expect_form_factor(m.f, "point", "disc", 1.5 * 1.5 / (1.5 * 1.5 + 4));
  expect_form_factor(m.f, "point", "environment", 4 / (1.5 * 1.5 + 4));
}

TEST(FormFactors, PointFacingASphere) {
  // F = (r / d)^2 for a differential area facing the center of a sphere at distance d.
  FormFactorOptions o;
  o.sources = {"point"};
  const Measured m = measure(R"(
[[object]]
type = "disk"
name = "point"
radius = 0.001
[[object]]
type = "sphere"
name = "ball"
radius = 0.7
transform = { translate = [0, 2.5, 0] }
)",
                             o);
  expect_form_factor(m.f, "point", "ball", (0.7 / 2.5) * (0.7 / 2.5));
}

TEST(FormFactors, PointBelowTheCenterOfARectangle) {
  // Four times the corner case F = (1 / 2 pi) [X / sqrt(1 + X^2) atan(Y / sqrt(1 + X^2)) +
  // Y / sqrt(1 + Y^2) atan(X / sqrt(1 + Y^2))], X = a / c, Y = b / c for a quarter a x b at
  // height c.
  const double a = 1.5 / 2, b = 0.8 / 2, c = 1.2, X = a / c, Y = b / c;
  const double corner = (X / std::sqrt(1 + X * X) * std::atan(Y / std::sqrt(1 + X * X)) +
                         Y / std::sqrt(1 + Y * Y) * std::atan(X / std::sqrt(1 + Y * Y))) /
                        (2 * kPi);
  FormFactorOptions o;
  o.sources = {"point"};
  const Measured m = measure(R"(
[[object]]
type = "disk"
name = "point"
radius = 0.001
[[object]]
type = "rectangle"
name = "patch"
center = [0, 1.2, 0]
edge_u = [1.5, 0, 0]
edge_v = [0, 0, 0.8]
)",
                             o);
  expect_form_factor(m.f, "point", "patch", 4 * corner);
  // Its own row: a patch facing down (edge_u x edge_v = -y) sees the point's tiny disc only.
  FormFactorOptions p;
  p.sources = {"patch"};
  const Measured n = measure(R"(
[[object]]
type = "rectangle"
name = "patch"
edge_u = [1.5, 0, 0]
edge_v = [0, 0, 0.8]
)",
                             p);
  EXPECT_NEAR(n.f.areas[0], 1.5 * 0.8, 1e-12);
}

TEST(FormFactors, ParallelCoaxialDiscsAndReciprocity) {
  // F12 = (X - sqrt(X^2 - 4 (R2/R1)^2)) / 2, X = 1 + (1 + R2^2) / R1^2, R_i = r_i / h; and
  // F21 = F12 A1 / A2.
  const double r1 = 1, r2 = 0.6, h = 0.8, R1 = r1 / h, R2 = r2 / h;
  const double X = 1 + (1 + R2 * R2) / (R1 * R1);
  const double F12 = 0.5 * (X - std::sqrt(X * X - 4 * (R2 / R1) * (R2 / R1)));
  const Measured m = measure(R"(
[[object]]
type = "disk"
name = "d1"
radius = 1
[[object]]
type = "disk"
name = "d2"
radius = 0.6
transform = { rotate = [180, 1, 0, 0], translate = [0, 0.8, 0] }
)");
  expect_form_factor(m.f, "d1", "d2", F12);
  expect_form_factor(m.f, "d2", "d1", F12 * (r1 * r1) / (r2 * r2));
  EXPECT_NEAR(m.f.areas[size_t(column(m.f, "d1"))], kPi, 1e-12);
  EXPECT_LT(m.f.worst_reciprocity_z, 3)
      << m.f.names[size_t(m.f.worst_i)] << " / " << m.f.names[size_t(m.f.worst_j)];
}

const char* kRoom = R"(
[[object]]
type = "box"
name = "room"
size = [4, 3, 5]
[[object]]
type = "sphere"
name = "ball"
radius = 0.7
transform = { translate = [0.5, -0.2, 0.3] }
[[object]]
type = "cylinder"
name = "post"
radius = 0.2
base = [-1, -1.4, -1]
top = [-1, 0, -1]
)";

TEST(FormFactors, RowsSumToOneInAClosedRoom) {
  FormFactorOptions o;
  o.inward = {"room"};
  o.origins = 1024;
  const Measured m = measure(kRoom, o);
  ASSERT_EQ(m.f.rows.size(), 3u);
  for (size_t r = 0; r < m.f.rows.size(); ++r) {
    double sum = 0;
    for (double x : m.f.F[r]) sum += x;
    EXPECT_NEAR(sum, 1, 1e-12) << m.f.names[size_t(m.f.rows[r])];
    EXPECT_EQ(m.f.F[r].back(), 0) << m.f.names[size_t(m.f.rows[r])] << " sees out of the room";
  }
  EXPECT_GT(m.f.F[size_t(row(m.f, "room"))][size_t(column(m.f, "room"))], 0.8)
      << "the room sees mostly itself";
  EXPECT_EQ(m.f.F[size_t(row(m.f, "ball"))][size_t(column(m.f, "ball"))], 0)
      << "a convex ball never sees itself";
  EXPECT_LT(m.f.worst_reciprocity_z, 3);
  EXPECT_NEAR(m.f.areas[size_t(column(m.f, "room"))], 2 * (4 * 3 + 4 * 5 + 3 * 5), 1e-9);
}

TEST(FormFactors, TheSameNumbersOnAnyNumberOfThreads) {
  FormFactorOptions o;
  o.inward = {"room"};
  o.origins = 200;
  const Measured a = measure(kRoom, o);
  Measured b;
  tbb::task_arena(1).execute([&] { b = measure(kRoom, o); });
  EXPECT_EQ(a.f.F, b.f.F);
  EXPECT_EQ(a.f.error, b.f.error);
}

TEST(FormFactors, MeshSourceFacingADisc) {
  // A tiny square of two triangles (an OBJ, counter-clockwise seen from +y) as the point.
  const auto dir =
      std::filesystem::temp_directory_path() / ("anamorph_ff_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "plate.obj") << "v -0.001 0 -0.001\nv 0.001 0 -0.001\nv 0.001 0 0.001\n"
                                      "v -0.001 0 0.001\nf 1 3 2\nf 1 4 3\n";
  const std::string toml =
      "[[object]]\ntype = \"mesh\"\nname = \"plate\"\nfile = \"" + (dir / "plate.obj").string() +
      "\"\n" +
      std::string(kPointFacingDisc)
          .substr(
              std::string(kPointFacingDisc).find("[[object]]\ntype = \"disk\"\nname = \"disc\""));
  const Measured m = measure(toml);
  ASSERT_FALSE(m.f.rows.empty());
  const std::string plate = m.f.names[size_t(m.f.rows[0])];
  expect_form_factor(m.f, plate, "disc", 1.5 * 1.5 / (1.5 * 1.5 + 4));
  std::filesystem::remove_all(dir);
}

TEST(Radiosity, ConcentricSpheresMatchTheAnalyticSolutionAndThePathTracer) {
  // A lamp sphere (Le = 1, rho 0.5) inside an inward-facing dome sphere (rho 0.6): by symmetry
  // each has one radiosity, so one patch per object is exact. F(lamp -> dome) = 1,
  // F(dome -> lamp) = (r / R)^2, F(dome -> dome) = 1 - (r / R)^2.
  const char* toml = R"(
[render]
integrator = "path"
[[material]]
name = "lamp"
color = 0.5
emission = 1
[[material]]
name = "wall"
color = 0.6
[[object]]
type = "sphere"
name = "lamp"
radius = 0.5
material = "lamp"
[[object]]
type = "sphere"
name = "dome"
radius = 2
material = "wall"
)";
  FormFactorOptions o;
  o.inward = {"dome"};
  o.origins = 1024;
  o.rays = 64;
  const Measured m = measure(toml, o);
  expect_form_factor(m.f, "dome", "lamp", 0.25 * 0.25);
  const std::vector<Color> B = solve_radiosity(m.scene, *m.accel, m.f);
  const double Foi = 0.25 * 0.25, k = 0.6 * Foi / (1 - 0.6 * (1 - Foi));
  const double Bi = kPi / (1 - 0.5 * k), Bo = k * Bi;
  const int lamp = column(m.f, "lamp"), dome = column(m.f, "dome");
  EXPECT_NEAR(B[size_t(lamp)].x, Bi, 0.002 * Bi);
  EXPECT_NEAR(B[size_t(dome)].x, Bo, 0.02 * Bo);  // F's own error, amplified by the dome's echo
  const PathRadiance p = path_traced_radiance(m.scene, *m.accel, m.f, o, 64);
  for (const int i : {lamp, dome}) {
    const double L = B[size_t(i)].x / kPi, se = p.error[size_t(i)].x;
    // The radiosity carries F's error too: allow 4 path standard errors plus 1 %.
    EXPECT_LE(std::abs(p.mean[size_t(i)].x - L), 4 * se + 0.01 * L)
        << m.f.names[size_t(i)] << ": radiosity " << L << ", path tracer " << p.mean[size_t(i)].x
        << " +- " << se;
  }
}

TEST(FormFactors, ErrorsNameTheObject) {
  const auto error_of = [](const std::string& toml, FormFactorOptions o) -> std::string {
    try {
      measure(toml, o);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "<accepted>";
  };
  FormFactorOptions unknown;
  unknown.sources = {"dics"};
  EXPECT_NE(error_of(kPointFacingDisc, unknown)
                .find("no object named 'dics' (the scene has: "
                      "point, disc)"),
            std::string::npos);
  FormFactorOptions plane;
  plane.sources = {"floor"};
  EXPECT_NE(error_of("[[object]]\ntype = \"plane\"\nname = \"floor\"\n", plane)
                .find("'floor' has no row of form factors: an infinite plane has no finite area"),
            std::string::npos);
  // Radiosity needs every object as a row.
  FormFactorOptions one;
  one.sources = {"point"};
  const Measured m = measure(kPointFacingDisc, one);
  EXPECT_THROW(solve_radiosity(m.scene, *m.accel, m.f), std::invalid_argument);
}

}  // namespace
}  // namespace anamorph
