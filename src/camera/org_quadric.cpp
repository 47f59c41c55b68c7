// Quadrics as affine images of canonical surfaces parameterized by longitude s and a second
// parameter t. Canonical space: x right, y up (the axis), z back; longitude 0 lies at -z and grows
// toward +x. The normal is the quadric's gradient mapped by the inverse transpose, so it stays
// outward under any affine map (also mirroring ones) and is defined at the poles.
#include "camera/org_quadric.h"

#include <cmath>

namespace anamorph {

namespace {

// Canonical point, derivatives and gradient G = H X + g0 (outward normal direction).
struct Canonical {
  LocalGeom g;
  Vec3 h, g0;  // diagonal of the (constant) Hessian, constant gradient part
};

Canonical canonical(QuadricKind kind, double s, double t) {
  const double cs = std::cos(s), ss = std::sin(s);
  Canonical c;
  LocalGeom& g = c.g;
  switch (kind) {
    case QuadricKind::Sphere: {  // x^2 + y^2 + z^2 = 1; t = latitude
      const double ct = std::cos(t), st = std::sin(t);
      g.p = {ss * ct, st, -cs * ct};
      g.ps = {cs * ct, 0, ss * ct};
      g.pt = {-ss * st, ct, cs * st};
      g.pss = {-ss * ct, 0, cs * ct};
      g.pst = {-cs * st, 0, -ss * st};
      g.ptt = {-ss * ct, -st, cs * ct};
      c.h = {1, 1, 1};
      break;
    }
    case QuadricKind::HyperboloidOneSheet: {  // x^2 + z^2 - y^2 = 1; y = sinh t
      const double ch = std::cosh(t), sh = std::sinh(t);
      g.p = {ch * ss, sh, -ch * cs};
      g.ps = {ch * cs, 0, ch * ss};
      g.pt = {sh * ss, ch, -sh * cs};
      g.pss = {-ch * ss, 0, ch * cs};
      g.pst = {sh * cs, 0, sh * ss};
      g.ptt = g.p;
      c.h = {1, -1, 1};
      break;
    }
    case QuadricKind::HyperboloidTwoSheets: {  // y^2 - x^2 - z^2 = 1, upper sheet; y = cosh t
      const double ch = std::cosh(t), sh = std::sinh(t);
      g.p = {sh * ss, ch, -sh * cs};
      g.ps = {sh * cs, 0, sh * ss};
      g.pt = {ch * ss, sh, -ch * cs};
      g.pss = {-sh * ss, 0, sh * cs};
      g.pst = {ch * cs, 0, ch * ss};
      g.ptt = g.p;
      c.h = {1, -1, 1};  // away from the inside of the bowl
      break;
    }
    case QuadricKind::Paraboloid: {  // y = x^2 + z^2; t = distance from the axis
      g.p = {t * ss, t * t, -t * cs};
      g.ps = {t * cs, 0, t * ss};
      g.pt = {ss, 2 * t, -cs};
      g.pss = {-t * ss, 0, t * cs};
      g.pst = {cs, 0, ss};
      g.ptt = {0, 2, 0};
      c.h = {2, 0, 2};
      c.g0 = {0, -1, 0};
      break;
    }
  }
  return c;
}

class QuadricOrg final : public OrgFunctionLoop<QuadricOrg> {
 public:
  QuadricOrg(QuadricKind kind, const Mat3& m, Vec3 origin, ParamRange sr, ParamRange tr, bool flip)
      : kind_(kind), m_(m), a_(m.inverse_transpose()), o_(origin), sr_(sr), tr_(tr), flip_(flip) {}

  bool eval(Vec2 uv, SurfaceSample* out) const override {
    const Canonical c = canonical(kind_, sr_(uv.x), tr_(uv.y));
    const double su = sr_.scale(), sv = tr_.scale();
    set_position(transform_geom(c.g, m_, o_), su, sv, out);
    const Vec3 G = c.h * c.g.p + c.g0;
    set_normal(a_ * G, a_ * (c.h * c.g.ps), a_ * (c.h * c.g.pt), su, sv, flip_, out);
    return true;
  }

 private:
  QuadricKind kind_;
  Mat3 m_, a_;
  Vec3 o_;
  ParamRange sr_, tr_;
  bool flip_;
};

constexpr std::string_view kLongitudeDoc =
    "Longitude range in degrees mapped onto image u: 0 at `front`, growing toward the right "
    "(the +x side for the default frame), so that org sphere + dir normal (looking outward) "
    "gives an unmirrored panorama. For cameras looking inward (flip_normal, dir toward the "
    "center) use [180, -180] to avoid a mirrored image.";

const ParamSpec kSphereParams[] = {
    {"center", ParamType::Vec3, "[0, 0, 0]", "Center of the sphere."},
    {.name = "radius",
     .type = ParamType::Number,
     .default_value = "1",
     .doc = "Radius.",
     .min = 0,
     .min_exclusive = true},
    {"axis", ParamType::Vec3, "[0, 1, 0]", "Pole direction (latitude +90)."},
    {"front", ParamType::Vec3, "none",
     "Direction of longitude 0 (projected perpendicular to `axis`); default -z, or +-y when the "
     "axis is along z."},
    {.name = "u_range",
     .type = ParamType::Vec2,
     .default_value = "[-180, 180]",
     .doc = kLongitudeDoc,
     .unit = "degrees"},
    {.name = "v_range",
     .type = ParamType::Vec2,
     .default_value = "[90, -90]",
     .doc =
         "Latitude range in degrees mapped onto image v (top to bottom): north pole at the top by "
         "default.",
     .unit = "degrees"},
    kFlipNormalParam,
};

const ParamSpec kEllipsoidParams[] = {
    {"center", ParamType::Vec3, "[0, 0, 0]", "Center of the ellipsoid."},
    {.name = "radii",
     .type = ParamType::Vec3,
     .default_value = "[1, 1, 1]",
     .doc =
         "Semi-axes along the local right, axis (up) and back directions (x, y, z for the default "
         "frame).",
     .min = 0,
     .min_exclusive = true},
    {"axis", ParamType::Vec3, "[0, 1, 0]", "Pole direction (latitude +90)."},
    {"front", ParamType::Vec3, "none",
     "Direction of longitude 0 (projected perpendicular to `axis`); default -z."},
    {.name = "u_range",
     .type = ParamType::Vec2,
     .default_value = "[-180, 180]",
     .doc = kLongitudeDoc,
     .unit = "degrees"},
    {.name = "v_range",
     .type = ParamType::Vec2,
     .default_value = "[90, -90]",
     .doc = "Latitude range in degrees (of the underlying sphere) mapped onto image v.",
     .unit = "degrees"},
    kFlipNormalParam,
};

const std::string_view kKinds[] = {"sphere", "hyperboloid_one_sheet", "hyperboloid_two_sheets",
                                   "paraboloid"};

const ParamSpec kQuadricParams[] = {
    {.name = "kind",
     .type = ParamType::String,
     .default_value = "\"sphere\"",
     .doc = "The canonical quadric: sphere x^2+y^2+z^2 = 1; hyperboloid_one_sheet x^2+z^2-y^2 = 1; "
            "hyperboloid_two_sheets y^2-x^2-z^2 = 1 (upper sheet); paraboloid y = x^2+z^2.",
     .choices = kKinds},
    {"matrix", ParamType::Vec3List, "[[1, 0, 0], [0, 1, 0], [0, 0, 1]]",
     "Linear part of the affine map, 3 rows: p = matrix * X + translation for canonical X. Any "
     "non-singular matrix (scales, rotations, shears, mirrors)."},
    {"translation", ParamType::Vec3, "[0, 0, 0]", "Translation of the affine map."},
    {.name = "u_range",
     .type = ParamType::Vec2,
     .default_value = "[-180, 180]",
     .doc = "Longitude around the canonical y axis in degrees (0 at -z, growing toward +x).",
     .unit = "degrees"},
    {.name = "v_range",
     .type = ParamType::Vec2,
     .default_value = "none",
     .doc = "Second parameter, top to bottom: latitude in degrees for sphere (default [90, -90]); "
            "t with "
            "y = sinh t for hyperboloid_one_sheet (default [1, -1]); t with y = cosh t for "
            "hyperboloid_two_sheets (default [1, 0]); the distance from the axis for paraboloid "
            "(default [1, 0]).",
     .unit = "degrees"},
    kFlipNormalParam,
};

std::unique_ptr<OrgFunction> create_sphere(const ParamValues& v) {
  check_params(kSphereParams, v);
  const AxisFrame f = read_axis_frame(v);
  const double r = v.number("radius");
  const Mat3 m{f.right * r, f.up * r, f.back * r};
  return make_quadric_org(QuadricKind::Sphere, m, v.vec3("center"), read_angle_range(v, "u_range"),
                          read_angle_range(v, "v_range"), v.boolean("flip_normal"));
}

std::unique_ptr<OrgFunction> create_ellipsoid(const ParamValues& v) {
  check_params(kEllipsoidParams, v);
  const AxisFrame f = read_axis_frame(v);
  const Vec3 r = v.vec3("radii");
  const Mat3 m{f.right * r.x, f.up * r.y, f.back * r.z};
  return make_quadric_org(QuadricKind::Sphere, m, v.vec3("center"), read_angle_range(v, "u_range"),
                          read_angle_range(v, "v_range"), v.boolean("flip_normal"));
}

std::unique_ptr<OrgFunction> create_quadric(const ParamValues& v) {
  check_params(kQuadricParams, v);
  const std::string& k = v.string("kind");
  const QuadricKind kind = k == "sphere"                   ? QuadricKind::Sphere
                           : k == "hyperboloid_one_sheet"  ? QuadricKind::HyperboloidOneSheet
                           : k == "hyperboloid_two_sheets" ? QuadricKind::HyperboloidTwoSheets
                                                           : QuadricKind::Paraboloid;
  const std::vector<Vec3>& rows = v.vec3s("matrix");
  if (rows.size() != 3)
    throw ParamError("matrix", "matrix needs exactly 3 rows of 3 numbers (got " +
                                   std::to_string(rows.size()) + " rows)");
  const Mat3 m{{rows[0].x, rows[1].x, rows[2].x},
               {rows[0].y, rows[1].y, rows[2].y},
               {rows[0].z, rows[1].z, rows[2].z}};
  if (!(std::abs(m.det()) > 1e-12 * length(m.c0) * length(m.c1) * length(m.c2)))
    throw ParamError("matrix", "matrix is singular (the surface would collapse)");
  ParamRange tr;
  if (v.has("v_range")) {
    tr = read_range(v, "v_range");
  } else {
    tr = kind == QuadricKind::Sphere                ? ParamRange{90, -90}
         : kind == QuadricKind::HyperboloidOneSheet ? ParamRange{1, -1}
                                                    : ParamRange{1, 0};
  }
  if (kind == QuadricKind::Sphere) tr = {radians(tr.a), radians(tr.b)};
  return make_quadric_org(kind, m, v.vec3("translation"), read_angle_range(v, "u_range"), tr,
                          v.boolean("flip_normal"));
}

}  // namespace

std::unique_ptr<OrgFunction> make_quadric_org(QuadricKind kind, const Mat3& m, Vec3 origin,
                                              ParamRange s_range, ParamRange t_range,
                                              bool flip_normal) {
  return std::make_unique<QuadricOrg>(kind, m, origin, s_range, t_range, flip_normal);
}

std::unique_ptr<OrgFunction> make_sphere_org(Vec3 center, double radius, ParamRange longitude,
                                             ParamRange latitude, bool flip_normal) {
  const Mat3 m{{radius, 0, 0}, {0, radius, 0}, {0, 0, radius}};
  return make_quadric_org(QuadricKind::Sphere, m, center,
                          {radians(longitude.a), radians(longitude.b)},
                          {radians(latitude.a), radians(latitude.b)}, flip_normal);
}

const OrgFunctionInfo kSphereOrgInfo{
    "sphere",
    "Part of a sphere parameterized by longitude (u) and latitude (v), the paper's sphere "
    "function. Outward normal. org sphere + dir normal looks outward (an equirectangular "
    "panorama from the sphere's surface); with dir toward its center it looks inward.",
    kSphereParams, create_sphere};
const OrgFunctionInfo kEllipsoidOrgInfo{
    "ellipsoid",
    "A sphere scaled by three semi-axes in its local frame; longitude (u) and latitude (v) as "
    "for sphere. Outward normal.",
    kEllipsoidParams, create_ellipsoid};
const OrgFunctionInfo kQuadricOrgInfo{
    "quadric",
    "A canonical quadric (sphere, hyperboloid of one or two sheets, paraboloid) through a "
    "general affine map p = matrix * X + translation: ellipsoids, elliptic hyperboloids and "
    "paraboloids in any position. u is the longitude around the canonical axis; the normal is "
    "the transformed gradient, pointing away from the axis / the inside of the bowl.",
    kQuadricParams, create_quadric};

}  // namespace anamorph
