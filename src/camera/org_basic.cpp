// Origin functions: point and plane.
#include "camera/org_basic.h"

#include "camera/org_common.h"

namespace anamorph {

namespace {

class PointOrg final : public OrgFunctionLoop<PointOrg> {
 public:
  explicit PointOrg(Vec3 p) : p_(p) {}
  bool eval(Vec2, SurfaceSample* out) const override {
    clear(out);
    out->p = p_;
    return true;
  }

 private:
  Vec3 p_;
};

// A rectilinear grid: p(u,v) = center + (u' - 1/2) edge_u + (v' - 1/2) edge_v, with u', v' the
// image position mapped through u_range / v_range.
class PlaneOrg final : public OrgFunctionLoop<PlaneOrg> {
 public:
  PlaneOrg(Vec3 center, Vec3 eu, Vec3 ev, ParamRange ur, ParamRange vr, bool flip)
      : c_(center),
        eu_(eu),
        ev_(ev),
        ur_(ur),
        vr_(vr),
        n_(normalize(cross(eu, ev)) * (flip ? -1.0 : 1.0)) {}
  bool eval(Vec2 uv, SurfaceSample* out) const override {
    const double s = ur_(uv.x) - 0.5, t = vr_(uv.y) - 0.5;
    clear(out);
    out->p = c_ + eu_ * s + ev_ * t;
    out->dpdu = eu_ * ur_.scale();
    out->dpdv = ev_ * vr_.scale();
    out->n = n_;
    return true;
  }

 private:
  Vec3 c_, eu_, ev_;
  ParamRange ur_, vr_;
  Vec3 n_;
};

const ParamSpec kPointParams[] = {
    {"position", ParamType::Vec3, "[0, 0, 0]", "The single origin of every ray."},
};

const ParamSpec kPlaneParams[] = {
    {"center", ParamType::Vec3, "[0, 0, 0]",
     "Center of the rectangle (image position (0.5, 0.5))."},
    {"edge_u", ParamType::Vec3, "[1, 0, 0]",
     "Full edge vector along u (left to right). Ignored when `size` is given."},
    {"edge_v", ParamType::Vec3, "[0, -1, 0]",
     "Full edge vector along v (top to bottom). Ignored when `size` is given."},
    {.name = "size",
     .type = ParamType::Vec2,
     .default_value = "none",
     .doc = "Width and height; with `normal` and `up` an alternative to edge_u/edge_v.",
     .min = 0,
     .min_exclusive = true},
    {"normal", ParamType::Vec3, "[0, 0, -1]",
     "Plane normal (with `size`): the side the image faces; u runs right and v down as seen "
     "looking along it."},
    {"up", ParamType::Vec3, "[0, 1, 0]",
     "Up vector in the plane (with `size`); need not be "
     "perpendicular to `normal`."},
    {"u_range", ParamType::Vec2, "[0, 1]",
     "Part of the rectangle along u (0 = left edge, 1 = right edge) mapped to the image; "
     "reversed if decreasing (mirrors the image); values outside [0, 1] extend the plane."},
    {"v_range", ParamType::Vec2, "[0, 1]",
     "Part of the rectangle along v (0 = top edge, 1 = bottom edge) mapped to the image; "
     "reversed if decreasing."},
    kFlipNormalParam,
};

std::unique_ptr<OrgFunction> create_point(const ParamValues& v) {
  check_params(kPointParams, v);
  return make_point_org(v.vec3("position"));
}

std::unique_ptr<OrgFunction> create_plane(const ParamValues& v) {
  check_params(kPlaneParams, v);
  Vec3 eu = v.vec3("edge_u"), ev = v.vec3("edge_v");
  if (v.has("size")) {
    const Vec2 size = v.vec2("size");
    const Vec3 n = v.vec3("normal"), up = v.vec3("up");
    if (!(length(n) > 0)) throw ParamError("normal", "normal must not be zero");
    const Vec3 r = cross(normalize(n), up);
    if (!(length(r) > 1e-12 * length(up)))
      throw ParamError("up", "up must not be zero or parallel to normal");
    // Looking along the normal, u runs right and v runs down; edge_u x edge_v = normal.
    const Vec3 right = normalize(r);
    const Vec3 down = normalize(cross(normalize(n), right));
    eu = right * size.x;
    ev = down * size.y;
  }
  if (!(length(cross(eu, ev)) > 0))
    throw ParamError("edge_u", "edge_u and edge_v must be non-zero and not parallel");
  return std::make_unique<PlaneOrg>(v.vec3("center"), eu, ev, read_range(v, "u_range"),
                                    read_range(v, "v_range"), v.boolean("flip_normal"));
}

}  // namespace

std::unique_ptr<OrgFunction> make_point_org(Vec3 p) { return std::make_unique<PointOrg>(p); }

std::unique_ptr<OrgFunction> make_plane_org(Vec3 center, Vec3 edge_u, Vec3 edge_v, ParamRange ur,
                                            ParamRange vr) {
  return std::make_unique<PlaneOrg>(center, edge_u, edge_v, ur, vr, false);
}

const OrgFunctionInfo kPointOrgInfo{"point", "A single point: every ray starts there (a pinhole).",
                                    kPointParams, create_point};
const OrgFunctionInfo kPlaneOrgInfo{
    "plane",
    "A rectilinear grid on a plane (the paper's plane function), given by its center and two "
    "edge vectors, or by size + normal + up. Normal = edge_u x edge_v: the side the image looks "
    "at. With dir = constant it is a parallel projection; with org = point and dir = from_surface "
    "plane, the ordinary perspective.",
    kPlaneParams, create_plane};

}  // namespace anamorph
