// Cylinder, cone and torus in a local frame (canonical x right, y = axis, z back; angle 0 at -z
// growing toward +x, as for the sphere's longitude). Normals are analytic and outward (away from
// the axis; for the torus away from the tube's core), so they exist at a cone's apex too.
#include "camera/org_revolution.h"

#include <cmath>

#include "camera/org_common.h"

namespace anamorph {

namespace {

enum class Kind { Cylinder, Cone, Torus };

class RevolutionOrg final : public OrgFunctionLoop<RevolutionOrg> {
 public:
  // a, b: cylinder radius; cone tan(half angle), unused; torus major and minor radius.
  RevolutionOrg(Kind kind, double a, double b, const AxisFrame& f, Vec3 origin, ParamRange sr,
                ParamRange tr, bool flip)
      : kind_(kind), a_(a), b_(b), m_(f.matrix()), o_(origin), sr_(sr), tr_(tr), flip_(flip) {}

  bool eval(Vec2 uv, SurfaceSample* out) const override {
    const double s = sr_(uv.x), t = tr_(uv.y);
    const double cs = std::cos(s), ss = std::sin(s);
    const Vec3 radial{ss, 0, -cs}, radial_s{cs, 0, ss}, y{0, 1, 0};
    LocalGeom g;
    Vec3 N, Ns, Nt;
    switch (kind_) {
      case Kind::Cylinder:  // X = r radial(s) + t y
        g = {radial * a_ + y * t, radial_s * a_, y, -radial * a_, {}, {}};
        N = radial;
        Ns = radial_s;
        break;
      case Kind::Cone: {  // X = t (tan(alpha) radial(s) + y), t >= 0 from the apex
        g = {(radial * a_ + y) * t, radial_s * (a_ * t), radial * a_ + y,
             -radial * (a_ * t),    radial_s * a_,       {}};
        // Perpendicular to the generator tan(alpha) radial + y, pointing away from the axis.
        const double inv = 1 / std::sqrt(1 + a_ * a_);
        N = (radial - y * a_) * inv;
        Ns = radial_s * inv;
        break;
      }
      case Kind::Torus: {  // X = (R + r cos t) radial(s) + r sin t y
        const double ct = std::cos(t), st = std::sin(t), w = a_ + b_ * ct;
        g = {radial * w + y * (b_ * st),
             radial_s * w,
             radial * (-b_ * st) + y * (b_ * ct),
             -radial * w,
             radial_s * (-b_ * st),
             radial * (-b_ * ct) - y * (b_ * st)};
        N = radial * ct + y * st;
        Ns = radial_s * ct;
        Nt = radial * -st + y * ct;
        break;
      }
    }
    const double su = sr_.scale(), sv = tr_.scale();
    set_position(transform_geom(g, m_, o_), su, sv, out);
    set_normal(m_ * N, m_ * Ns, m_ * Nt, su, sv, flip_, out);
    return true;
  }

 private:
  Kind kind_;
  double a_, b_;
  Mat3 m_;
  Vec3 o_;
  ParamRange sr_, tr_;
  bool flip_;
};

constexpr std::string_view kAngleDoc =
    "Angle around the axis in degrees mapped onto image u: 0 at `front`, growing toward the right "
    "as seen from the axis looking at `front` with `axis` up (so org + dir normal, looking "
    "outward, is unmirrored; use [180, -180] when looking inward).";
constexpr std::string_view kFrontDoc =
    "Direction of angle 0, projected perpendicular to `axis`; default -z (or +-y when the axis is "
    "along z).";

const ParamSpec kCylinderParams[] = {
    {"center", ParamType::Vec3, "[0, 0, 0]", "A point on the axis (height 0)."},
    {"axis", ParamType::Vec3, "[0, 1, 0]",
     "Axis direction (any non-zero vector, e.g. [1, -1, -1] for the line through (-1, 1, 1) "
     "and (1, -1, -1) with center [0, 0, 0])."},
    {"front", ParamType::Vec3, "none", kFrontDoc},
    {.name = "radius",
     .type = ParamType::Number,
     .default_value = "1",
     .doc = "Radius.",
     .min = 0,
     .min_exclusive = true},
    {.name = "u_range",
     .type = ParamType::Vec2,
     .default_value = "[-180, 180]",
     .doc = kAngleDoc,
     .unit = "degrees"},
    {"v_range", ParamType::Vec2, "[1, -1]",
     "Height range along the normalized axis, measured from `center`, mapped onto image v (top "
     "to bottom)."},
    kFlipNormalParam,
};

const ParamSpec kConeParams[] = {
    {"apex", ParamType::Vec3, "[0, 0, 0]", "The tip of the cone."},
    {"axis", ParamType::Vec3, "[0, 1, 0]", "Axis direction from the apex into the cone."},
    {"front", ParamType::Vec3, "none", kFrontDoc},
    {.name = "half_angle",
     .type = ParamType::Number,
     .default_value = "45",
     .doc = "Angle between the axis and the surface, degrees.",
     .min = 0,
     .max = 90,
     .min_exclusive = true,
     .max_exclusive = true,
     .unit = "degrees"},
    {.name = "u_range",
     .type = ParamType::Vec2,
     .default_value = "[-180, 180]",
     .doc = kAngleDoc,
     .unit = "degrees"},
    {.name = "v_range",
     .type = ParamType::Vec2,
     .default_value = "[1, 0]",
     .doc = "Distance from the apex along the normalized axis mapped onto image v (top to bottom); "
            "[h0, h1] with h0 > 0 gives a frustum.",
     .min = 0},
    kFlipNormalParam,
};

const ParamSpec kTorusParams[] = {
    {"center", ParamType::Vec3, "[0, 0, 0]", "Center of the torus."},
    {"axis", ParamType::Vec3, "[0, 1, 0]", "Axis of revolution."},
    {"front", ParamType::Vec3, "none", kFrontDoc},
    {.name = "major_radius",
     .type = ParamType::Number,
     .default_value = "1",
     .doc = "Distance from the axis to the tube's core.",
     .min = 0,
     .min_exclusive = true},
    {.name = "minor_radius",
     .type = ParamType::Number,
     .default_value = "0.25",
     .doc = "Radius of the tube.",
     .min = 0,
     .min_exclusive = true},
    {.name = "u_range",
     .type = ParamType::Vec2,
     .default_value = "[-180, 180]",
     .doc = kAngleDoc,
     .unit = "degrees"},
    {.name = "v_range",
     .type = ParamType::Vec2,
     .default_value = "[180, -180]",
     .doc =
         "Angle around the tube in degrees mapped onto image v: 0 on the outer equator, 90 on top, "
         "180 on the inner equator. The default puts the outer equator in the middle row with the "
         "top above it.",
     .unit = "degrees"},
    kFlipNormalParam,
};

std::unique_ptr<OrgFunction> create_cylinder(const ParamValues& v) {
  check_params(kCylinderParams, v);
  return std::make_unique<RevolutionOrg>(Kind::Cylinder, v.number("radius"), 0, read_axis_frame(v),
                                         v.vec3("center"), read_angle_range(v, "u_range"),
                                         read_range(v, "v_range"), v.boolean("flip_normal"));
}

std::unique_ptr<OrgFunction> create_cone(const ParamValues& v) {
  check_params(kConeParams, v);
  return std::make_unique<RevolutionOrg>(
      Kind::Cone, std::tan(radians(v.number("half_angle"))), 0, read_axis_frame(v), v.vec3("apex"),
      read_angle_range(v, "u_range"), read_range(v, "v_range"), v.boolean("flip_normal"));
}

std::unique_ptr<OrgFunction> create_torus(const ParamValues& v) {
  check_params(kTorusParams, v);
  return std::make_unique<RevolutionOrg>(Kind::Torus, v.number("major_radius"),
                                         v.number("minor_radius"), read_axis_frame(v),
                                         v.vec3("center"), read_angle_range(v, "u_range"),
                                         read_angle_range(v, "v_range"), v.boolean("flip_normal"));
}

}  // namespace

const OrgFunctionInfo kCylinderOrgInfo{
    "cylinder",
    "Part of a circular cylinder around any axis (the paper's cylinder function): u is the angle "
    "around the axis, v the height. With dir = normal it gives the cylinder projections of "
    "cartography.",
    kCylinderParams, create_cylinder};
const OrgFunctionInfo kConeOrgInfo{
    "cone",
    "Part of a circular cone (or frustum): u is the angle around the axis, v the distance from "
    "the apex along the axis. Outward normal, defined at the apex too.",
    kConeParams, create_cone};
const OrgFunctionInfo kTorusOrgInfo{
    "torus",
    "Part of a torus: u is the angle around the axis, v the angle around the tube. Outward "
    "normal.",
    kTorusParams, create_torus};

}  // namespace anamorph
