// Analytic surfaces: every sample satisfies the surface's implicit equation, normals point the
// documented way, and the documented orientation of (u, v) holds.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "camera/functions.h"
#include "function_test_util.h"

namespace anamorph {
namespace {

using test::cat;
using test::expect_close;
using test::sample;
using test::str;

// Calls check(uv, sample) on a grid covering the whole image, edges included.
void for_grid(const OrgFunction& f, const std::function<void(Vec2, const SurfaceSample&)>& check,
              int n = 24) {
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const Vec2 uv{double(i) / n, double(j) / n};
      check(uv, sample(f, uv));
    }
}

// The local frame the docs promise: up = axis, back = -(front projected), right = up x back.
struct Frame3 {
  Vec3 right, up, back;
  Vec3 local(const Vec3& d) const { return {dot(d, right), dot(d, up), dot(d, back)}; }
};
Frame3 frame(Vec3 axis, Vec3 front) {
  Frame3 f;
  f.up = normalize(axis);
  f.back = -normalize(front - f.up * dot(front, f.up));
  f.right = cross(f.up, f.back);
  return f;
}

TEST(SphereOrg, PointsOnSphereWithOutwardNormals) {
  const Vec3 c{1, -2, 0.5};
  const auto f = make_org("sphere", "center = [1, -2, 0.5]\nradius = 2.5\naxis = [1, 1, 0]");
  for_grid(*f, [&](Vec2 uv, const SurfaceSample& s) {
    EXPECT_NEAR(length(s.p - c), 2.5, 1e-12) << "at " << uv.x << ", " << uv.y;
    expect_close(s.n, (s.p - c) / 2.5, 1e-12, "outward normal");
  });
}

TEST(SphereOrg, DefaultOrientation) {
  // Longitude 0 (image center) at -z, growing toward +x (the right of a viewer at the center
  // looking down -z with +y up); the north pole (+y) at the image's top.
  const auto f = make_org("sphere", "radius = 2");
  expect_close(sample(*f, {0.5, 0.5}).p, {0, 0, -2}, 1e-12, "image center");
  expect_close(sample(*f, {0.75, 0.5}).p, {2, 0, 0}, 1e-12, "three quarters right");
  expect_close(sample(*f, {0.25, 0.5}).p, {-2, 0, 0}, 1e-12, "one quarter");
  expect_close(sample(*f, {0.0, 0.5}).p, {0, 0, 2}, 1e-12, "left edge (behind)");
  expect_close(sample(*f, {0.3, 0.0}).p, {0, 2, 0}, 1e-12, "top = north pole");
  expect_close(sample(*f, {0.3, 1.0}).p, {0, -2, 0}, 1e-12, "bottom = south pole");
  // At the poles the normal is still defined.
  expect_close(sample(*f, {0.3, 0.0}).n, {0, 1, 0}, 1e-12, "normal at the pole");
}

TEST(SphereOrg, FrameFollowsAxisAndFront) {
  const Vec3 axis{0.2, 0.3, 1}, front{1, 0, 0};
  const Frame3 fr = frame(axis, front);
  const auto f = make_org("sphere", "axis = [0.2, 0.3, 1]\nfront = [1, 0, 0]");
  expect_close(sample(*f, {0.5, 0.5}).p, -fr.back, 1e-12, "longitude 0 at front");
  expect_close(sample(*f, {0.75, 0.5}).p, fr.right, 1e-12, "longitude 90 at right");
  expect_close(sample(*f, {0.5, 0.0}).p, fr.up, 1e-12, "pole on the axis");
  // Right-handed: right x up = back.
  expect_close(cross(fr.right, fr.up), fr.back, 1e-12, "handedness");
}

TEST(CylinderOrg, ArbitraryAxisThroughTwoPoints) {
  // The axis is the line through (-1, 1, 1) and (1, -1, -1).
  const Vec3 a{-1, 1, 1}, b{1, -1, -1}, d = normalize(b - a);
  for (const char* center : {"[0, 0, 0]", "[-1, 1, 1]"}) {
    const auto f = make_org(
        "cylinder",
        cat("center = ", center, "\naxis = [1, -1, -1]\nradius = 0.75", "\nv_range = [-2, 3]"));
    for_grid(*f, [&](Vec2 uv, const SurfaceSample& s) {
      const double dist = length(cross(s.p - a, d));
      EXPECT_NEAR(dist, 0.75, 1e-12) << "at " << uv.x << ", " << uv.y << " p = " << str(s.p);
      // The outward normal is the direction away from the axis.
      const Vec3 foot = a + d * dot(s.p - a, d);
      expect_close(s.n, (s.p - foot) / 0.75, 1e-12, "outward normal");
    });
    // v runs along the axis: the height difference between top and bottom is the v_range span.
    EXPECT_NEAR(dot(sample(*f, {0.3, 1}).p - sample(*f, {0.3, 0}).p, d), 5, 1e-12);
  }
}

TEST(ConeOrg, ImplicitEquationAndApexNormal) {
  const Vec3 apex{1, 1, 1};
  const Vec3 axis = normalize(Vec3{0.3, -1, 0.2});
  const double ta = std::tan(radians(25));
  const auto f = make_org("cone",
                          "apex = [1, 1, 1]\naxis = [0.3, -1, 0.2]\nhalf_angle = 25\n"
                          "v_range = [3, 0]");
  for_grid(*f, [&](Vec2 uv, const SurfaceSample& s) {
    const Vec3 d = s.p - apex;
    const double h = dot(d, axis), radial = length(d - axis * h);
    EXPECT_GE(h, -1e-12);
    EXPECT_NEAR(radial, h * ta, 1e-12) << "at " << uv.x << ", " << uv.y;
    // Normal: unit, perpendicular to the generator, pointing away from the axis.
    EXPECT_NEAR(length(s.n), 1, 1e-12);
    if (radial > 1e-9) {
      const Vec3 out = (d - axis * h) / radial;
      EXPECT_NEAR(dot(s.n, axis * std::cos(radians(25)) + out * std::sin(radians(25))), 0, 1e-12);
      EXPECT_GT(dot(s.n, out), 0);
    }
  });
  // At the apex (v = 1) the point is the apex and the normal still exists.
  const SurfaceSample tip = sample(*f, {0.4, 1.0});
  expect_close(tip.p, apex, 1e-12, "apex");
  EXPECT_NEAR(length(tip.n), 1, 1e-12);
}

TEST(TorusOrg, ImplicitEquation) {
  const Vec3 c{0, 1, -2};
  const Frame3 fr = frame({1, 1, 0}, {0, 0, -1});
  const auto f = make_org("torus",
                          "center = [0, 1, -2]\naxis = [1, 1, 0]\nmajor_radius = 2\n"
                          "minor_radius = 0.5");
  for_grid(*f, [&](Vec2 uv, const SurfaceSample& s) {
    const Vec3 q = fr.local(s.p - c);
    const double ring = std::hypot(q.x, q.z) - 2;
    EXPECT_NEAR(ring * ring + q.y * q.y, 0.25, 1e-12) << "at " << uv.x << ", " << uv.y;
    // Outward: away from the tube's core circle.
    const Vec3 core = c + (fr.right * q.x + fr.back * q.z) * (2 / std::hypot(q.x, q.z));
    expect_close(s.n, (s.p - core) / 0.5, 1e-12, "outward normal");
  });
  // The middle row is the outer equator, the quarter row the top of the tube.
  const SurfaceSample mid = sample(*f, {0.5, 0.5}), top = sample(*f, {0.5, 0.25});
  EXPECT_NEAR(length(mid.p - c), 2.5, 1e-12);
  EXPECT_NEAR(dot(top.p - c, fr.up), 0.5, 1e-12);
}

TEST(SuperquadricOrg, ImplicitEquation) {
  const Vec3 c{0.5, 0, 1}, r{1, 2, 0.5};
  for (const auto& exponents :
       {std::pair{1.0, 1.0}, std::pair{0.3, 1.7}, std::pair{2.0, 0.5}, std::pair{0.8, 2.0}}) {
    // (Not a structured binding: clang 14 cannot capture one in the lambda below.)
    const double ens = exponents.first, eew = exponents.second;
    const auto f = make_org("superquadric",
                            cat("center = [0.5, 0, 1]\nradii = [1, 2, 0.5]\naxis = [0, 0, 1]\n",
                                "exponent_ns = ", ens, "\nexponent_ew = ", eew));
    const Frame3 fr = frame({0, 0, 1}, {0, 1, 0});  // the documented default front for axis z
    for_grid(*f, [&](Vec2 uv, const SurfaceSample& s) {
      const Vec3 q = fr.local(s.p - c);
      const double xz =
          std::pow(std::abs(q.x / r.x), 2 / eew) + std::pow(std::abs(q.z / r.z), 2 / eew);
      const double F = std::pow(xz, eew / ens) + std::pow(std::abs(q.y / r.y), 2 / ens);
      EXPECT_NEAR(F, 1, 1e-10) << "exponents " << ens << ", " << eew << " at " << uv.x << ", "
                               << uv.y;
      EXPECT_NEAR(length(s.n), 1, 1e-12);
      EXPECT_GE(dot(s.n, s.p - c), -1e-12) << "normal points outward (star-shaped about c)";
    });
  }
}

// Solves m x = b for a 3x3 matrix given by rows.
Vec3 solve(const Vec3 rows[3], const Vec3& b) {
  const Vec3 c0{rows[0].x, rows[1].x, rows[2].x}, c1{rows[0].y, rows[1].y, rows[2].y},
      c2{rows[0].z, rows[1].z, rows[2].z};
  const double det = dot(c0, cross(c1, c2));
  return {dot(b, cross(c1, c2)) / det, dot(c0, cross(b, c2)) / det, dot(c0, cross(c1, b)) / det};
}

TEST(QuadricOrg, AffineUnitSphereIsTheEllipsoid) {
  const Vec3 rows[3] = {{1, 0.5, -0.3}, {0.2, 2, 0.3}, {0, -0.4, 1.5}};
  const Vec3 t{1, 2, 3};
  const auto f = make_org("quadric",
                          "matrix = [[1, 0.5, -0.3], [0.2, 2, 0.3], [0, -0.4, 1.5]]\n"
                          "translation = [1, 2, 3]");
  for_grid(*f, [&](Vec2 uv, const SurfaceSample& s) {
    // (p - t)^T (M M^T)^-1 (p - t) = |M^-1 (p - t)|^2 = 1
    const Vec3 x = solve(rows, s.p - t);
    EXPECT_NEAR(length_squared(x), 1, 1e-12) << "at " << uv.x << ", " << uv.y;
    // The ellipsoid's gradient (M M^T)^-1 (p - t) = M^-T x is the outward normal.
    const Vec3 cols_t[3] = {{rows[0].x, rows[1].x, rows[2].x},
                            {rows[0].y, rows[1].y, rows[2].y},
                            {rows[0].z, rows[1].z, rows[2].z}};  // rows of M^T
    const Vec3 g = solve(cols_t, x);                             // M^-T x
    expect_close(s.n, normalize(g), 1e-12, "normal = normalized gradient");
  });
}

TEST(QuadricOrg, OtherKindsSatisfyTheirEquations) {
  const Vec3 rows[3] = {{2, 0, 0.5}, {0, 1, 0}, {0.3, 0, 1}};
  const std::string m = "matrix = [[2, 0, 0.5], [0, 1, 0], [0.3, 0, 1]]\ntranslation = [0, 1, 0]";
  const std::pair<const char*, std::function<double(Vec3)>> kinds[] = {
      {"hyperboloid_one_sheet", [](Vec3 x) { return x.x * x.x + x.z * x.z - x.y * x.y - 1; }},
      {"hyperboloid_two_sheets", [](Vec3 x) { return x.y * x.y - x.x * x.x - x.z * x.z - 1; }},
      {"paraboloid", [](Vec3 x) { return x.x * x.x + x.z * x.z - x.y; }},
  };
  for (const auto& entry : kinds) {
    const char* kind = entry.first;  // (clang 14 cannot capture a structured binding)
    const auto& implicit = entry.second;
    const auto f = make_org("quadric", cat("kind = \"", kind, "\"\n", m));
    for_grid(*f, [&](Vec2 uv, const SurfaceSample& s) {
      const Vec3 x = solve(rows, s.p - Vec3{0, 1, 0});
      EXPECT_NEAR(implicit(x), 0, 1e-11) << kind << " at " << uv.x << ", " << uv.y;
      if (std::string(kind) == "hyperboloid_two_sheets") {
        EXPECT_GT(x.y, 0) << "upper sheet";
      }
    });
  }
}

TEST(EllipsoidOrg, EqualsQuadricWithDiagonalMatrix) {
  const auto e = make_org("ellipsoid", "center = [1, 2, 3]\nradii = [1, 2, 3]");
  const auto q = make_org("quadric",
                          "matrix = [[1, 0, 0], [0, 2, 0], [0, 0, 3]]\n"
                          "translation = [1, 2, 3]");
  for_grid(*e, [&](Vec2 uv, const SurfaceSample& s) {
    const SurfaceSample o = sample(*q, uv);
    expect_close(s.p, o.p, 1e-12, "p");
    expect_close(s.n, o.n, 1e-12, "n");
    expect_close(s.dndv, o.dndv, 1e-12, "dndv");
  });
}

}  // namespace
}  // namespace anamorph
