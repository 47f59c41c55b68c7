// Bezier, B-spline and NURBS origin functions over a control net given as rows of points: the
// first row is the image's top edge, each row runs left to right. The normal is dp/du x dp/dv of
// the surface's own parameters, the side the image looks at when the net is laid out as the
// viewer sees it (as for plane).
#include "camera/org_spline.h"

#include <cmath>
#include <limits>

namespace anamorph {

namespace {

class SplineOrg final : public OrgFunction {
 public:
  SplineOrg(SplineSurface s, ParamRange ur, ParamRange vr, bool flip)
      : s_(std::move(s)), flip_(flip) {
    // Compose image -> domain fraction -> knot parameter into one linear map per direction.
    const double ws = s_.s_hi() - s_.s_lo(), wt = s_.t_hi() - s_.t_lo();
    sr_ = {s_.s_lo() + ws * ur.a, s_.s_lo() + ws * ur.b};
    tr_ = {s_.t_lo() + wt * vr.a, s_.t_lo() + wt * vr.b};
  }

  bool eval(Vec2 uv, SurfaceSample* out) const override {
    return eval_as_batch_of_one(*this, uv, out);
  }

  void eval_batch(const double* u, const double* v, int n, SurfaceBatch* out) const override {
    double ss[kCameraBatch], ts[kCameraBatch];
    for (int k = 0; k < n; ++k) ss[k] = sr_(u[k]), ts[k] = tr_(v[k]);
    LocalGeomBatch g;
    s_.eval_batch(ss, ts, n, &g);
    bool check[kCameraBatch];
    const double ms = min_ds(), mt = min_dt();
    cross_normal_batch(g, sr_.scale(), tr_.scale(), flip_, ms * ms, mt * mt, n, out, check);
    for (int k = 0; k < n; ++k)
      if (check[k]) {
        SurfaceSample x;
        finish(g.lane(k), ss[k], ts[k], &x);
        out->set(k, x);
      }
  }

 private:
  // Where the net collapses (a row of equal points, as at a NURBS sphere's pole) d/ds or d/dt
  // vanishes and the cross product is noise: below these lengths the normal is taken a hair
  // inside the domain (finish).
  double min_ds() const { return 1e-9 * s_.size() / (s_.s_hi() - s_.s_lo()); }
  double min_dt() const { return 1e-9 * s_.size() / (s_.t_hi() - s_.t_lo()); }

  // One sample the batch kernel flagged (and, for usable derivatives, what the kernel computes).
  void finish(const LocalGeom& g, double s, double t, SurfaceSample* out) const {
    const double su = sr_.scale(), sv = tr_.scale(), ms = min_ds(), mt = min_dt();
    set_position(g, su, sv, out);
    const Vec3 N = cross(g.ps, g.pt);
    const double ps2 = dot(g.ps, g.ps), pt2 = dot(g.pt, g.pt);
    if (ps2 > ms * ms && pt2 > mt * mt && dot(N, N) > 1e-18 * ps2 * pt2) {
      set_cross_normal(g, su, sv, flip_, out);
      return;
    }
    const auto inward = [](double x, double lo, double hi) {
      return x + (0.5 * (lo + hi) >= x ? 1e-6 : -1e-6) * (hi - lo);
    };
    const LocalGeom h = s_.eval(inward(s, s_.s_lo(), s_.s_hi()), inward(t, s_.t_lo(), s_.t_hi()));
    set_normal(cross(h.ps, h.pt), {}, {}, su, sv, flip_, out);
  }

  SplineSurface s_;
  ParamRange sr_, tr_;
  bool flip_;
};

// --- parameters ---

constexpr std::string_view kKnotTypes[] = {"clamped", "uniform"};

constexpr std::string_view kPointsDoc =
    "Control net: rows of [x, y, z] points. The first row is the image's top edge, each row runs "
    "left to right; all rows have the same length.";
constexpr std::string_view kURangeDoc =
    "Part of the valid parameter domain along u mapped to the image, as fractions (0 = first "
    "column, 1 = last); reversed if decreasing.";
constexpr std::string_view kVRangeDoc =
    "Part of the valid parameter domain along v mapped to the image, as fractions (0 = first row, "
    "1 = last); reversed if decreasing.";

constexpr ParamSpec kBSplineCore[] = {
    {"points", ParamType::Vec3Grid, "", kPointsDoc},
    {.name = "degree_u",
     .type = ParamType::Integer,
     .default_value = "3",
     .doc = "Degree along u (across a row); below the number of points per row.",
     .min = 1,
     .max = spline::kMaxDegree},
    {.name = "degree_v",
     .type = ParamType::Integer,
     .default_value = "3",
     .doc = "Degree along v (down the rows); below the number of rows.",
     .min = 1,
     .max = spline::kMaxDegree},
    {.name = "knot_type_u",
     .type = ParamType::String,
     .default_value = "\"clamped\"",
     .doc = "Knot vector along u when `knots_u` is not given: clamped (open uniform: the surface "
            "reaches the first and last control columns) or uniform (unclamped, evenly spaced).",
     .choices = kKnotTypes},
    {.name = "knot_type_v",
     .type = ParamType::String,
     .default_value = "\"clamped\"",
     .doc = "Knot vector along v, as knot_type_u.",
     .choices = kKnotTypes},
    {"knots_u", ParamType::NumberList, "none",
     "Explicit knot vector along u: non-decreasing, (points per row + degree_u + 1) values "
     "(overrides knot_type_u)."},
    {"knots_v", ParamType::NumberList, "none",
     "Explicit knot vector along v: non-decreasing, (rows + degree_v + 1) values."},
    {.name = "u_range",
     .type = ParamType::Vec2,
     .default_value = "[0, 1]",
     .doc = kURangeDoc,
     .min = 0,
     .max = 1},
    {.name = "v_range",
     .type = ParamType::Vec2,
     .default_value = "[0, 1]",
     .doc = kVRangeDoc,
     .min = 0,
     .max = 1},
};

const ParamSpec kBezierParams[] = {
    {"points", ParamType::Vec3Grid, "", kPointsDoc},
    {.name = "weights",
     .type = ParamType::NumberGrid,
     .default_value = "none",
     .doc = "Optional weights, one per control point in the same rows (rational Bezier).",
     .min = 0,
     .min_exclusive = true},
    {.name = "u_range",
     .type = ParamType::Vec2,
     .default_value = "[0, 1]",
     .doc = kURangeDoc,
     .min = 0,
     .max = 1},
    {.name = "v_range",
     .type = ParamType::Vec2,
     .default_value = "[0, 1]",
     .doc = kVRangeDoc,
     .min = 0,
     .max = 1},
    kFlipNormalParam,
};

constexpr auto kBSplineParams = join_params(kBSplineCore, kFlipNormalParam);

constexpr auto kNurbsParams = join_params(
    kBSplineCore,
    ParamSpec{.name = "weights",
              .type = ParamType::NumberGrid,
              .default_value = "",
              .doc = "Weights, one per control point in the same rows as `points` (all 1 = the "
                     "B-spline).",
              .min = 0,
              .min_exclusive = true},
    kFlipNormalParam);

SplineNet read_net(const ParamValues& v, bool need_weights) {
  const auto& rows = v.vec3_grid("points");
  SplineNet net;
  net.nv = int(rows.size());
  net.nu = rows.empty() ? 0 : int(rows[0].size());
  if (net.nv < 2 || net.nu < 2)
    throw ParamError("points", "points needs at least 2 rows of at least 2 points (got " +
                                   std::to_string(net.nv) + " rows of " + std::to_string(net.nu) +
                                   ")");
  for (size_t j = 0; j < rows.size(); ++j) {
    if (int(rows[j].size()) != net.nu)
      throw ParamError("points", "points: row " + std::to_string(j) + " has " +
                                     std::to_string(rows[j].size()) + " points but row 0 has " +
                                     std::to_string(net.nu) + "; all rows need the same length");
    net.points.insert(net.points.end(), rows[j].begin(), rows[j].end());
  }
  if (need_weights || v.has("weights")) {
    const auto& w = v.number_grid("weights");
    if (int(w.size()) != net.nv)
      throw ParamError("weights", "weights has " + std::to_string(w.size()) +
                                      " rows but points has " + std::to_string(net.nv));
    for (size_t j = 0; j < w.size(); ++j) {
      if (int(w[j].size()) != net.nu)
        throw ParamError(
            "weights", "weights: row " + std::to_string(j) + " has " + std::to_string(w[j].size()) +
                           " values but the rows of points have " + std::to_string(net.nu));
      for (double x : w[j])
        if (!(x > 0)) throw ParamError("weights", "weights must be > 0");
      net.weights.insert(net.weights.end(), w[j].begin(), w[j].end());
    }
  }
  return net;
}

std::vector<double> read_knots(const ParamValues& v, char dir, int num_ctrl, int degree) {
  const std::string d(1, dir);
  const std::string count = dir == 'u' ? "points per row" : "rows";
  if (degree >= num_ctrl)
    throw ParamError("degree_" + d, "degree_" + d + " (" + std::to_string(degree) +
                                        ") must be less than the number of control " + count +
                                        " (" + std::to_string(num_ctrl) + ")");
  if (v.has("knots_" + d)) {
    std::vector<double> k = v.numbers("knots_" + d);
    const std::string problem = spline::knot_vector_problem(k, num_ctrl, degree);
    if (!problem.empty()) throw ParamError("knots_" + d, "knots_" + d + ": " + problem);
    return k;
  }
  return v.string("knot_type_" + d) == "uniform" ? spline::uniform_knots(num_ctrl, degree)
                                                 : spline::clamped_knots(num_ctrl, degree);
}

std::unique_ptr<OrgFunction> create_bspline_like(const ParamValues& v, bool rational) {
  SplineNet net = read_net(v, rational);
  const int p = int(v.integer("degree_u")), q = int(v.integer("degree_v"));
  std::vector<double> ku = read_knots(v, 'u', net.nu, p), kv = read_knots(v, 'v', net.nv, q);
  return make_spline_org(SplineSurface(std::move(net), p, q, SplineSurface::Basis::BSpline,
                                       std::move(ku), std::move(kv)),
                         read_range(v, "u_range"), read_range(v, "v_range"),
                         v.boolean("flip_normal"));
}

std::unique_ptr<OrgFunction> create_bezier(const ParamValues& v) {
  check_params(kBezierParams, v);
  SplineNet net = read_net(v, false);
  if (net.nu - 1 > spline::kMaxBezierDegree || net.nv - 1 > spline::kMaxBezierDegree)
    throw ParamError("points", "points: at most " + std::to_string(spline::kMaxBezierDegree + 1) +
                                   " points per row and rows (degree " +
                                   std::to_string(spline::kMaxBezierDegree) + ")");
  const int p = net.nu - 1, q = net.nv - 1;
  return make_spline_org(SplineSurface(std::move(net), p, q, SplineSurface::Basis::Bernstein),
                         read_range(v, "u_range"), read_range(v, "v_range"),
                         v.boolean("flip_normal"));
}

std::unique_ptr<OrgFunction> create_bspline(const ParamValues& v) {
  check_params(kBSplineParams, v);
  return create_bspline_like(v, false);
}

std::unique_ptr<OrgFunction> create_nurbs(const ParamValues& v) {
  check_params(kNurbsParams, v);
  return create_bspline_like(v, true);
}

}  // namespace

std::unique_ptr<OrgFunction> make_spline_org(SplineSurface surface, ParamRange ur, ParamRange vr,
                                             bool flip_normal) {
  return std::make_unique<SplineOrg>(std::move(surface), ur, vr, flip_normal);
}

const OrgFunctionInfo kBezierOrgInfo{
    "bezier",
    "A tensor-product Bezier surface of any degree up to 31 (points per row - 1 by rows - 1), "
    "optionally rational. Interpolates the four corner points.",
    kBezierParams, create_bezier};
const OrgFunctionInfo kBSplineOrgInfo{
    "bspline",
    "A tensor-product B-spline surface of degrees degree_u x degree_v (up to 15) with clamped, "
    "uniform or explicit knot vectors. Clamped knots make it interpolate the corner points.",
    kBSplineParams, create_bspline};
const OrgFunctionInfo kNurbsOrgInfo{
    "nurbs",
    "A NURBS surface: the B-spline with a positive weight per control point, which represents "
    "conics exactly (e.g. a sphere patch with weights 1, sqrt(2)/2, 1).",
    kNurbsParams, create_nurbs};

}  // namespace anamorph
