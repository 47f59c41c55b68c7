// Superellipsoid: the sphere's longitude/latitude parameterization with signed powers,
//   X = (a C(lat)^e_ns S(lon)^e_ew, b S(lat)^e_ns, -c C(lat)^e_ns C(lon)^e_ew),
// implicit (|x/a|^(2/e_ew) + |z/c|^(2/e_ew))^(e_ew/e_ns) + |y/b|^(2/e_ns) = 1, and the normal
// from the dual superquadric (exponents 2 - e), which is finite for exponents in (0, 2].
#include "camera/org_superquadric.h"

#include <algorithm>
#include <cmath>

#include "camera/org_common.h"

namespace anamorph {

namespace {

// sign(x) |x|^e of x(angle) and its first two derivatives with respect to the angle.
struct Pow {
  double f, d, dd;
};
Pow signed_pow(double x, double dx, double ddx, double e) {
  // With e < 1 the derivative is infinite where x = 0 (a crease of the parameterization);
  // clamping |x| keeps differentials finite there.
  const double ax = std::max(std::abs(x), 1e-9), sg = x > 0 ? 1.0 : (x < 0 ? -1.0 : 0.0);
  const double p1 = e * std::pow(ax, e - 1);
  return {sg * std::pow(std::abs(x), e), p1 * dx,
          e * (e - 1) * std::pow(ax, e - 2) * sg * dx * dx + p1 * ddx};
}

class SuperquadricOrg final : public OrgFunctionLoop<SuperquadricOrg> {
 public:
  SuperquadricOrg(Vec3 radii, double e_ns, double e_ew, const AxisFrame& f, Vec3 center,
                  ParamRange sr, ParamRange tr, bool flip)
      : r_(radii),
        e_ns_(e_ns),
        e_ew_(e_ew),
        m_(f.matrix()),
        o_(center),
        sr_(sr),
        tr_(tr),
        flip_(flip) {}

  bool eval(Vec2 uv, SurfaceSample* out) const override {
    const double s = sr_(uv.x), t = tr_(uv.y);
    const double cs = std::cos(s), ss = std::sin(s), ct = std::cos(t), st = std::sin(t);
    // Point: lon terms in s, lat terms in t.
    const Pow sl = signed_pow(ss, cs, -ss, e_ew_), cl = signed_pow(cs, -ss, -cs, e_ew_);
    const Pow sp = signed_pow(st, ct, -st, e_ns_), cp = signed_pow(ct, -st, -ct, e_ns_);
    LocalGeom g;
    g.p = {r_.x * cp.f * sl.f, r_.y * sp.f, -r_.z * cp.f * cl.f};
    g.ps = {r_.x * cp.f * sl.d, 0, -r_.z * cp.f * cl.d};
    g.pt = {r_.x * cp.d * sl.f, r_.y * sp.d, -r_.z * cp.d * cl.f};
    g.pss = {r_.x * cp.f * sl.dd, 0, -r_.z * cp.f * cl.dd};
    g.pst = {r_.x * cp.d * sl.d, 0, -r_.z * cp.d * cl.d};
    g.ptt = {r_.x * cp.dd * sl.f, r_.y * sp.dd, -r_.z * cp.dd * cl.f};
    // Normal: the same form with exponents 2 - e and inverse radii.
    const Pow nsl = signed_pow(ss, cs, -ss, 2 - e_ew_), ncl = signed_pow(cs, -ss, -cs, 2 - e_ew_);
    const Pow nsp = signed_pow(st, ct, -st, 2 - e_ns_), ncp = signed_pow(ct, -st, -ct, 2 - e_ns_);
    const Vec3 N{ncp.f * nsl.f / r_.x, nsp.f / r_.y, -ncp.f * ncl.f / r_.z};
    const Vec3 Ns{ncp.f * nsl.d / r_.x, 0, -ncp.f * ncl.d / r_.z};
    const Vec3 Nt{ncp.d * nsl.f / r_.x, nsp.d / r_.y, -ncp.d * ncl.f / r_.z};
    const double su = sr_.scale(), sv = tr_.scale();
    set_position(transform_geom(g, m_, o_), su, sv, out);
    set_normal(m_ * N, m_ * Ns, m_ * Nt, su, sv, flip_, out);
    return true;
  }

 private:
  Vec3 r_;
  double e_ns_, e_ew_;
  Mat3 m_;
  Vec3 o_;
  ParamRange sr_, tr_;
  bool flip_;
};

const ParamSpec kParams[] = {
    {"center", ParamType::Vec3, "[0, 0, 0]", "Center."},
    {.name = "radii",
     .type = ParamType::Vec3,
     .default_value = "[1, 1, 1]",
     .doc = "Semi-axes along the local right, axis (up) and back directions.",
     .min = 0,
     .min_exclusive = true},
    {"axis", ParamType::Vec3, "[0, 1, 0]", "Pole direction (latitude +90)."},
    {"front", ParamType::Vec3, "none",
     "Direction of longitude 0 (projected perpendicular to `axis`); default -z."},
    {.name = "exponent_ns",
     .type = ParamType::Number,
     .default_value = "1",
     .doc = "North-south exponent (profile along the axis): 1 round, toward 0 square, 2 pointed.",
     .min = 0,
     .max = 2,
     .min_exclusive = true},
    {.name = "exponent_ew",
     .type = ParamType::Number,
     .default_value = "1",
     .doc =
         "East-west exponent (cross-section around the axis): 1 round, toward 0 square, 2 diamond.",
     .min = 0,
     .max = 2,
     .min_exclusive = true},
    {.name = "u_range",
     .type = ParamType::Vec2,
     .default_value = "[-180, 180]",
     .doc = "Longitude range in degrees mapped onto image u, as for sphere (0 at `front`, growing "
            "toward "
            "the right seen from inside).",
     .unit = "degrees"},
    {.name = "v_range",
     .type = ParamType::Vec2,
     .default_value = "[90, -90]",
     .doc = "Latitude range in degrees mapped onto image v.",
     .unit = "degrees"},
    kFlipNormalParam,
};

std::unique_ptr<OrgFunction> create(const ParamValues& v) {
  check_params(kParams, v);
  return std::make_unique<SuperquadricOrg>(
      v.vec3("radii"), v.number("exponent_ns"), v.number("exponent_ew"), read_axis_frame(v),
      v.vec3("center"), read_angle_range(v, "u_range"), read_angle_range(v, "v_range"),
      v.boolean("flip_normal"));
}

}  // namespace

const OrgFunctionInfo kSuperquadricOrgInfo{
    "superquadric",
    "A superellipsoid with two exponents (Barr): from a rounded cube (exponents near 0) through "
    "the ellipsoid (1, 1) to an octahedron (2, 2). Parameterized like the sphere (longitude u, "
    "latitude v); outward normal.",
    kParams, create};

}  // namespace anamorph
