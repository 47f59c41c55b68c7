// B-spline, NURBS and Bezier: basis function identities, interpolation, exact conics, and the
// equivalences between the three surface types.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "camera/bspline.h"
#include "camera/functions.h"
#include "camera/org_spline.h"
#include "camera/spline_surface.h"
#include "function_test_util.h"

namespace anamorph {
namespace {

using test::batch_samples;
using test::cat;
using test::expect_close;
using test::expect_same_bits;
using test::sample;
using test::str;

struct KnotCase {
  std::vector<double> knots;
  int p;
};

std::vector<KnotCase> knot_cases() {
  std::vector<KnotCase> k;
  for (int p = 1; p <= 5; ++p) k.push_back({spline::clamped_knots(p + 4, p), p});
  k.push_back({spline::clamped_knots(16, 15), 15});
  k.push_back({spline::uniform_knots(7, 3), 3});
  k.push_back({{0, 0, 0, 0, 0.1, 0.1, 0.5, 2, 2, 2, 2}, 3});       // interior double knot
  k.push_back({{-1, -0.5, 0, 0.2, 0.2, 0.2, 1.7, 3, 4, 4.5}, 3});  // unclamped, non-uniform
  k.push_back({{0, 0, 0, 0.25, 0.5, 0.5, 0.75, 1, 1, 1}, 2});
  return k;
}

// All num_ctrl basis functions (and derivatives) at t, scattered from the span-local arrays.
std::vector<std::array<double, 3>> full_basis(const KnotCase& c, double t) {
  const int n = int(c.knots.size()) - c.p - 2;  // last control index
  const int span = spline::find_span(n, c.p, t, c.knots);
  spline::BasisDers d;
  spline::ders_basis_funs(span, t, c.p, 2, c.knots, d);
  std::vector<std::array<double, 3>> all(size_t(n + 1), {0, 0, 0});
  for (int j = 0; j <= c.p; ++j)
    for (int k = 0; k < 3; ++k) all[size_t(span - c.p + j)][size_t(k)] = d[k][j];
  return all;
}

TEST(BSplineBasis, PartitionOfUnityAndDerivatives) {
  for (const KnotCase& c : knot_cases()) {
    const int n = int(c.knots.size()) - c.p - 2;
    const double lo = c.knots[size_t(c.p)], hi = c.knots[size_t(n + 1)];
    ASSERT_EQ(spline::knot_vector_problem(c.knots, n + 1, c.p), "");
    for (int i = 0; i <= 200; ++i) {
      const double t = lo + (hi - lo) * i / 200.0;
      const int span = spline::find_span(n, c.p, t, c.knots);
      ASSERT_LE(c.knots[size_t(span)], t);
      ASSERT_TRUE(t < c.knots[size_t(span + 1)] || (t == hi && c.knots[size_t(span + 1)] == hi));
      double plain[spline::kMaxDegree + 1];
      spline::basis_funs(span, t, c.p, c.knots, plain);
      spline::BasisDers d;
      spline::ders_basis_funs(span, t, c.p, 2, c.knots, d);
      double s0 = 0, s1 = 0, s2 = 0;
      for (int j = 0; j <= c.p; ++j) {
        EXPECT_NEAR(plain[j], d[0][j], 1e-14) << "A2.2 and A2.3 disagree, p = " << c.p;
        EXPECT_GE(d[0][j], -1e-15) << "basis functions are non-negative";
        s0 += d[0][j];
        s1 += d[1][j];
        s2 += d[2][j];
      }
      EXPECT_NEAR(s0, 1, 1e-13) << "p = " << c.p << " t = " << t;
      EXPECT_NEAR(s1, 0, 1e-9 * (1 + std::abs(d[1][0]))) << "p = " << c.p << " t = " << t;
      EXPECT_NEAR(s2, 0, 1e-7 * (1 + std::abs(d[2][0]))) << "p = " << c.p << " t = " << t;
    }
  }
}

TEST(BSplineBasis, DerivativesMatchFiniteDifferences) {
  for (const KnotCase& c : knot_cases()) {
    if (c.p > 5) continue;  // high-degree values are tiny; the identities above cover them
    const int n = int(c.knots.size()) - c.p - 2;
    const double lo = c.knots[size_t(c.p)], hi = c.knots[size_t(n + 1)], h = 1e-6;
    for (int i = 1; i < 50; ++i) {
      const double t = lo + (hi - lo) * (i + 0.37) / 50.0;
      // Skip samples within h of a knot, where derivatives of order >= continuity jump.
      bool near_knot = false;
      for (double k : c.knots) near_knot |= std::abs(k - t) < 2 * h;
      if (near_knot) continue;
      const auto b = full_basis(c, t), bp = full_basis(c, t + h), bm = full_basis(c, t - h);
      for (size_t j = 0; j < b.size(); ++j) {
        EXPECT_NEAR(b[j][1], (bp[j][0] - bm[j][0]) / (2 * h), 1e-6 * (1 + std::abs(b[j][1])))
            << "N'_" << j << " p = " << c.p << " t = " << t;
        if (c.p >= 2) {
          EXPECT_NEAR(b[j][2], (bp[j][1] - bm[j][1]) / (2 * h), 1e-5 * (1 + std::abs(b[j][2])))
              << "N''_" << j << " p = " << c.p << " t = " << t;
        }
      }
    }
  }
}

TEST(BernsteinBasis, EqualsClampedBSplineWithoutInteriorKnots) {
  for (int p = 1; p <= 12; ++p) {
    const KnotCase c{spline::clamped_knots(p + 1, p), p};
    for (int i = 0; i <= 40; ++i) {
      const double t = i / 40.0;
      spline::BasisDers bz;
      spline::bernstein_ders(p, t, bz);
      const auto b = full_basis(c, t);
      double sum = 0;
      for (int j = 0; j <= p; ++j) {
        sum += bz[0][j];
        for (int k = 0; k < 3; ++k)
          EXPECT_NEAR(bz[k][j], b[size_t(j)][size_t(k)], 1e-9 * (1 + std::abs(bz[k][j])))
              << "derivative " << k << " of B_" << j << "," << p << " at " << t;
      }
      EXPECT_NEAR(sum, 1, 1e-13);
    }
  }
}

TEST(BSplineBasis, KnotValidation) {
  EXPECT_NE(spline::knot_vector_problem(std::vector<double>{0, 0, 1, 1}, 3, 1), "") << "too short";
  EXPECT_NE(spline::knot_vector_problem(std::vector<double>{0, 0, 0.5, 0.4, 1, 1}, 4, 1), "")
      << "decreasing";
  EXPECT_NE(spline::knot_vector_problem(std::vector<double>{0, 0, 0, 0, 0, 0}, 4, 1), "")
      << "empty domain";
  EXPECT_NE(spline::knot_vector_problem(std::vector<double>{0, 0, 0.5, 0.5, 0.5, 1, 1}, 5, 1), "")
      << "interior knot repeated beyond the degree";
  EXPECT_EQ(spline::knot_vector_problem(std::vector<double>{0, 0, 0.5, 1, 1}, 3, 1), "");
}

// --- surfaces ---

std::string grid_text(const std::vector<std::vector<Vec3>>& rows) {
  std::string s = "[";
  for (size_t j = 0; j < rows.size(); ++j) {
    s += j ? ", [" : "[";
    for (size_t i = 0; i < rows[j].size(); ++i)
      s += cat(i ? ", [" : "[", rows[j][i].x, ", ", rows[j][i].y, ", ", rows[j][i].z, "]");
    s += "]";
  }
  return s + "]";
}
std::string grid_text(const std::vector<std::vector<double>>& rows) {
  std::string s = "[";
  for (size_t j = 0; j < rows.size(); ++j) {
    s += j ? ", [" : "[";
    for (size_t i = 0; i < rows[j].size(); ++i) s += cat(i ? ", " : "", rows[j][i]);
    s += "]";
  }
  return s + "]";
}

std::vector<std::vector<Vec3>> wavy_net(int nu, int nv) {
  std::vector<std::vector<Vec3>> rows(static_cast<size_t>(nv));
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i)
      rows[size_t(j)].push_back({i + 0.2 * j, -j + 0.05 * i * j, std::cos(0.9 * i - 0.4 * j)});
  return rows;
}

std::vector<std::vector<double>> some_weights(int nu, int nv) {
  std::vector<std::vector<double>> w(static_cast<size_t>(nv));
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) w[size_t(j)].push_back(0.4 + 0.25 * ((3 * i + 5 * j) % 4));
  return w;
}

void expect_same_surface(const OrgFunction& a, const OrgFunction& b, double tol,
                         const std::string& what) {
  for (int j = 0; j <= 10; ++j)
    for (int i = 0; i <= 10; ++i) {
      const Vec2 uv{i / 10.0, j / 10.0};
      const SurfaceSample x = sample(a, uv), y = sample(b, uv);
      const std::string at = cat(what, " at (", uv.x, ", ", uv.y, ")");
      expect_close(x.p, y.p, tol, cat("p ", at));
      expect_close(x.dpdu, y.dpdu, tol, cat("dpdu ", at));
      expect_close(x.dpdv, y.dpdv, tol, cat("dpdv ", at));
      expect_close(x.dpduv, y.dpduv, tol * 10, cat("dpduv ", at));
      expect_close(x.n, y.n, tol, cat("n ", at));
    }
}

TEST(SplineOrg, ClampedSurfaceInterpolatesCorners) {
  const auto net = wavy_net(6, 5);
  for (const char* type : {"bspline", "nurbs", "bezier"}) {
    std::string t = cat("points = ", grid_text(net));
    if (std::string(type) != "bezier") t += "\ndegree_u = 3\ndegree_v = 2";
    if (std::string(type) == "nurbs") t += cat("\nweights = ", grid_text(some_weights(6, 5)));
    const auto f = make_org(type, t);
    expect_close(sample(*f, {0, 0}).p, net[0][0], 1e-14, cat(type, " top-left"));
    expect_close(sample(*f, {1, 0}).p, net[0][5], 1e-14, cat(type, " top-right"));
    expect_close(sample(*f, {0, 1}).p, net[4][0], 1e-14, cat(type, " bottom-left"));
    expect_close(sample(*f, {1, 1}).p, net[4][5], 1e-14, cat(type, " bottom-right"));
  }
}

TEST(SplineOrg, PlanarNetGivesPlanarSurface) {
  // Points on the plane through o spanned by a, b, irregularly placed within it.
  const Vec3 o{1, 2, 3}, a{1, 0.5, -0.2}, b{0.1, -1, 0.7};
  const Vec3 normal = normalize(cross(a, b));
  std::vector<std::vector<Vec3>> rows(5);
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 6; ++i)
      rows[size_t(j)].push_back(o + a * (i + 0.3 * std::sin(i * j)) + b * (j + 0.2 * std::cos(i)));
  const auto f =
      make_org("bspline", cat("points = ", grid_text(rows), "\nknot_type_u = \"uniform\""));
  for (int j = 0; j <= 20; ++j)
    for (int i = 0; i <= 20; ++i) {
      const SurfaceSample s = sample(*f, {i / 20.0, j / 20.0});
      EXPECT_NEAR(dot(s.p - o, normal), 0, 1e-12) << "point " << str(s.p) << " off the plane";
      EXPECT_NEAR(std::abs(dot(s.n, normal)), 1, 1e-12) << "normal " << str(s.n);
      EXPECT_NEAR(length(s.dndu) + length(s.dndv), 0, 1e-9) << "a plane's normal is constant";
    }
}

TEST(SplineOrg, NurbsWithUnitWeightsEqualsBSpline) {
  const auto net = wavy_net(5, 6);
  const std::string common = cat("points = ", grid_text(net),
                                 "\ndegree_u = 2\ndegree_v = 3\nknots_v = [0, 0, 0, 0, 0.3, 0.7, "
                                 "1, 1, 1, 1]");
  const auto b = make_org("bspline", common);
  const auto n = make_org(
      "nurbs", cat(common, "\nweights = ",
                   grid_text(std::vector<std::vector<double>>(6, std::vector<double>(5, 1.0)))));
  expect_same_surface(*n, *b, 1e-12, "unit-weight NURBS vs B-spline");
  // A common factor on all weights changes nothing either.
  const auto n3 = make_org(
      "nurbs", cat(common, "\nweights = ",
                   grid_text(std::vector<std::vector<double>>(6, std::vector<double>(5, 3.0)))));
  expect_close(sample(*n3, {0.3, 0.6}).p, sample(*b, {0.3, 0.6}).p, 1e-12, "scaled weights");
}

// The octant of the unit sphere x, y, z >= 0 as a biquadratic rational surface: a quarter
// circle profile (weights 1, sqrt(2)/2, 1) swept by a quarter circle around y.
std::unique_ptr<OrgFunction> sphere_octant() {
  const double w = std::sqrt(0.5);
  const double r[3] = {1, 1, 0}, y[3] = {0, 1, 1}, wp[3] = {1, w, 1};
  const double ax[3] = {1, 1, 0}, az[3] = {0, 1, 1}, wr[3] = {1, w, 1};
  std::vector<std::vector<Vec3>> pts(3);
  std::vector<std::vector<double>> ws(3);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) {
      pts[size_t(j)].push_back({r[j] * ax[i], y[j], r[j] * az[i]});
      ws[size_t(j)].push_back(wp[j] * wr[i]);
    }
  return make_org("nurbs", cat("points = ", grid_text(pts), "\nweights = ", grid_text(ws),
                               "\ndegree_u = 2\ndegree_v = 2"));
}

TEST(SplineOrg, NurbsReproducesSphereOctantExactly) {
  const auto f = sphere_octant();
  for (int j = 0; j <= 40; ++j)
    for (int i = 0; i <= 40; ++i) {
      const Vec2 uv{i / 40.0, j / 40.0};
      const SurfaceSample s = sample(*f, uv);
      EXPECT_NEAR(length(s.p), 1, 1e-12) << "at (" << uv.x << ", " << uv.y << ") p = " << str(s.p);
      EXPECT_GE(min_component(s.p), -1e-15);
      // Rows run from the equator to the pole and columns from +x to +z, so dp/du x dp/dv points
      // into the sphere; the fallback at the collapsed pole row keeps the same orientation.
      const double tol = j == 40 ? 1e-5 : 1e-9;
      expect_close(s.n, -s.p, tol, cat("normal at (", uv.x, ", ", uv.y, ")"));
    }
}

TEST(SplineOrg, NurbsReproducesQuarterCylinderExactly) {
  // A quarter circle of radius 2 in the xz-plane, extruded along y (linear in v).
  const double w = std::sqrt(0.5);
  const std::vector<std::vector<Vec3>> pts = {{{2, 1, 0}, {2, 1, 2}, {0, 1, 2}},
                                              {{2, -1, 0}, {2, -1, 2}, {0, -1, 2}}};
  const std::vector<std::vector<double>> ws = {{1, w, 1}, {1, w, 1}};
  const auto f = make_org("nurbs", cat("points = ", grid_text(pts), "\nweights = ", grid_text(ws),
                                       "\ndegree_u = 2\ndegree_v = 1"));
  for (int j = 0; j <= 10; ++j)
    for (int i = 0; i <= 100; ++i) {
      const SurfaceSample s = sample(*f, {i / 100.0, j / 10.0});
      EXPECT_NEAR(std::hypot(s.p.x, s.p.z), 2, 1e-12) << str(s.p);
      EXPECT_NEAR(s.p.y, 1 - 2 * j / 10.0, 1e-12) << str(s.p);
    }
}

TEST(SplineOrg, BezierEqualsClampedBSplineOfSameDegree) {
  for (const auto& [nu, nv] : {std::pair{4, 3}, std::pair{2, 6}, std::pair{7, 7}}) {
    const auto net = wavy_net(nu, nv);
    const auto bz = make_org("bezier", cat("points = ", grid_text(net)));
    const auto bs = make_org("bspline", cat("points = ", grid_text(net), "\ndegree_u = ", nu - 1,
                                            "\ndegree_v = ", nv - 1));
    expect_same_surface(*bz, *bs, 1e-12, cat("bezier ", nu, "x", nv));
    const auto w = some_weights(nu, nv);
    const auto rbz =
        make_org("bezier", cat("points = ", grid_text(net), "\nweights = ", grid_text(w)));
    const auto nb = make_org("nurbs", cat("points = ", grid_text(net), "\nweights = ", grid_text(w),
                                          "\ndegree_u = ", nu - 1, "\ndegree_v = ", nv - 1));
    expect_same_surface(*rbz, *nb, 1e-12, cat("rational bezier ", nu, "x", nv));
  }
}

// Packets of degree <= 3 take each row's curve in power form per knot span; the basis-function
// evaluation (de Boor's recurrences) is the reference: same geometry and derivatives to rounding,
// for every degree, clamped, uniform and explicit knots with a double knot, rational or not.
TEST(SplineSurface, PowerFormRowsMatchBasisFunctions) {
  const int nu = 7, nv = 6;
  for (int p = 1; p <= 4; ++p)
    for (int knots = 0; knots < 3; ++knots)
      for (bool rational : {false, true}) {
        if (knots == 2 && p == 1) continue;  // degree 1 allows no double knot
        SplineNet net;
        net.nu = nu, net.nv = nv;
        for (const auto& row : wavy_net(nu, nv))
          net.points.insert(net.points.end(), row.begin(), row.end());
        if (rational)
          for (const auto& row : some_weights(nu, nv))
            net.weights.insert(net.weights.end(), row.begin(), row.end());
        std::vector<double> ku = knots == 0   ? spline::clamped_knots(nu, p)
                                 : knots == 1 ? spline::uniform_knots(nu, p)
                                              : spline::clamped_knots(nu, p);
        if (knots == 2) ku[size_t(p) + 2] = ku[size_t(p) + 1];  // a double interior knot
        ASSERT_EQ(spline::knot_vector_problem(ku, nu, p), "") << p << " " << knots;
        const SplineSurface S(net, p, 2, SplineSurface::Basis::BSpline, ku,
                              spline::clamped_knots(nv, 2));
        const std::string what = cat("degree ", p, " knots ", knots, rational ? " rational" : "");
        // 4x4 packets of pixel centers and a packet of scattered positions with the domain ends.
        for (int packet = 0; packet < 6; ++packet) {
          double ss[kCameraBatch], ts[kCameraBatch];
          for (int k = 0; k < kCameraBatch; ++k) {
            const double fu =
                packet < 5 ? (packet * 13 + k % 4 + 0.5) / 68 : std::fmod(k * 0.618034, 1.0);
            const double fv = packet < 5 ? (packet * 7 + k / 4 + 0.5) / 38 : (k % 3) / 2.0;
            ss[k] = S.s_lo() + (S.s_hi() - S.s_lo()) * (packet == 5 && k == 15 ? 1.0 : fu);
            ts[k] = S.t_lo() + (S.t_hi() - S.t_lo()) * fv;
          }
          LocalGeomBatch b;
          S.eval_batch(ss, ts, kCameraBatch, &b);
          for (int k = 0; k < kCameraBatch; ++k) {
            const LocalGeom e = S.eval(ss[k], ts[k]), g = b.lane(k);
            const std::string at = cat(what, " at (", ss[k], ", ", ts[k], ")");
            expect_close(g.p, e.p, 1e-13, "p " + at);
            expect_close(g.ps, e.ps, 1e-12, "ps " + at);
            expect_close(g.pt, e.pt, 1e-12, "pt " + at);
            expect_close(g.pss, e.pss, 1e-11, "pss " + at);
            expect_close(g.pst, e.pst, 1e-11, "pst " + at);
            expect_close(g.ptt, e.ptt, 1e-11, "ptt " + at);
          }
        }
      }
}

TEST(SplineOrg, UnsortedPacketsMatchEvalBitForBit) {
  const auto f = make_org(
      "nurbs", cat("points = ", grid_text(wavy_net(9, 8)),
                   "\nweights = ", grid_text(some_weights(9, 8)), "\ndegree_u = 3\ndegree_v = 3"));
  // Packets that cross knot spans, partly unsorted, with repeats and the domain ends.
  std::vector<Vec2> at;
  for (int j = 0; j < 70; ++j)
    for (int i = 0; i < 23; ++i)
      at.push_back({i == 22 ? 1.0 : std::fmod(i * 0.618034, 1.0),
                    j < 40 ? j / 39.0 : std::fmod(j * 0.3819, 1.0)});
  const std::vector<SurfaceSample> batch = batch_samples(*f, at);
  for (size_t i = 0; i < at.size(); ++i)
    expect_same_bits(batch[i], sample(*f, at[i]), cat(i, " at (", at[i].x, ", ", at[i].y, ")"));
}

}  // namespace
}  // namespace anamorph
