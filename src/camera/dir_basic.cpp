// Direction functions independent of the origin surface's shape: constant, from_surface, and
// toward / away_from a point.
#include "camera/dir_basic.h"

namespace anamorph {

namespace {

class ConstantDir final : public DirFunctionLoop<ConstantDir> {
 public:
  explicit ConstantDir(Vec3 d) : d_(d) {}
  bool eval(Vec2, const SurfaceSample&, DirSample* out) const override {
    *out = DirSample{d_, {}, {}};
    return true;
  }

 private:
  Vec3 d_;
};

// The paper's "sphere function for dir" generalized to any surface: the direction from a fixed
// center to the surface point. When the surface does not enclose the center, two (u, v) can give
// the same direction (the mirroring circle), and moving the surface away from the center zooms.
class SurfaceDir final : public DirFunctionLoop<SurfaceDir> {
 public:
  SurfaceDir(std::unique_ptr<OrgFunction> s, Vec3 c) : s_(std::move(s)), c_(c) {}
  bool eval(Vec2 uv, const SurfaceSample&, DirSample* out) const override {
    SurfaceSample s;
    if (!s_->eval(uv, &s)) return false;
    *out = DirSample{s.p - c_, s.dpdu, s.dpdv};
    return true;
  }

 private:
  std::unique_ptr<OrgFunction> s_;
  Vec3 c_;
};

// sign = +1: dir = point - org; sign = -1: dir = org - point. A ray whose origin is the point
// itself has no direction (zero length: the camera reports no ray).
class PointDir final : public DirFunctionLoop<PointDir> {
 public:
  PointDir(Vec3 p, double sign) : p_(p), sign_(sign) {}
  bool eval(Vec2, const SurfaceSample& o, DirSample* out) const override {
    *out = DirSample{(p_ - o.p) * sign_, o.dpdu * -sign_, o.dpdv * -sign_};
    return true;
  }

 private:
  Vec3 p_;
  double sign_;
};

const ParamSpec kConstantParams[] = {
    {"direction", ParamType::Vec3, "[0, 0, -1]", "The direction of every ray (need not be unit)."},
};

const ParamSpec kFromSurfaceParams[] = {
    {"surface", ParamType::Function, "",
     "Any origin function, e.g. { type = \"sphere\", ... }; its point at (u, v) gives the "
     "direction."},
    {"center", ParamType::Vec3, "[0, 0, 0]",
     "The coordinate center c (camera space; default the camera's origin): dir(u,v) = S(u,v) - "
     "c. A sphere around c gives all directions; a sphere not enclosing c gives a restricted "
     "cone of directions with a mirroring circle (where the line from c touches the sphere), "
     "and moving it away from c zooms in."},
};

const ParamSpec kTowardParams[] = {
    {"point", ParamType::Vec3, "[0, 0, 0]",
     "Every ray aims at this point: dir = point - org (no ray where org is the point)."},
};

const ParamSpec kAwayFromParams[] = {
    {"point", ParamType::Vec3, "[0, 0, 0]",
     "Every ray leaves away from this point: dir = org - point (no ray where org is the point)."},
};

std::unique_ptr<DirFunction> create_constant(const ParamValues& v) {
  check_params(kConstantParams, v);
  const Vec3 d = v.vec3("direction");
  if (!(length(d) > 0)) throw ParamError("direction", "direction must not be zero");
  return make_constant_dir(d);
}

std::unique_ptr<DirFunction> create_from_surface(const ParamValues& v) {
  check_params(kFromSurfaceParams, v);
  const NestedFunction& f = v.function("surface");
  const OrgFunctionInfo* info = find_org_function(f.type);
  if (!info) throw ParamError("surface", "unknown surface type '" + f.type + "'");
  try {
    return make_surface_dir(info->create(f.values), v.vec3("center"));
  } catch (const ParamError& e) {
    // Name the nested key so the parser can point at it.
    throw ParamError("surface." + e.key, e.what());
  }
}

std::unique_ptr<DirFunction> create_toward(const ParamValues& v) {
  check_params(kTowardParams, v);
  return make_toward_dir(v.vec3("point"));
}

std::unique_ptr<DirFunction> create_away_from(const ParamValues& v) {
  check_params(kAwayFromParams, v);
  return make_away_from_dir(v.vec3("point"));
}

}  // namespace

std::unique_ptr<DirFunction> make_constant_dir(Vec3 d) { return std::make_unique<ConstantDir>(d); }
std::unique_ptr<DirFunction> make_surface_dir(std::unique_ptr<OrgFunction> s, Vec3 c) {
  return std::make_unique<SurfaceDir>(std::move(s), c);
}
std::unique_ptr<DirFunction> make_toward_dir(Vec3 p) { return std::make_unique<PointDir>(p, 1.0); }
std::unique_ptr<DirFunction> make_away_from_dir(Vec3 p) {
  return std::make_unique<PointDir>(p, -1.0);
}

const DirFunctionInfo kConstantDirInfo{
    "constant",
    "Every ray has the same direction: a parallel projection with a plane org, a parallel "
    "projection onto a curved image surface with any other org.",
    kConstantParams, create_constant};
const DirFunctionInfo kFromSurfaceDirInfo{
    "from_surface",
    "Directions from a surface: dir(u,v) = S(u,v) - center, for any origin function S (the "
    "paper's sphere / cylinder / plane functions for dir). org = point with a plane S is the "
    "ordinary perspective projection.",
    kFromSurfaceParams, create_from_surface};
const DirFunctionInfo kTowardDirInfo{
    "toward", "Every ray aims at one point: dir = point - org (e.g. org sphere around an object).",
    kTowardParams, create_toward};
const DirFunctionInfo kAwayFromDirInfo{
    "away_from",
    "Every ray points away from one point: dir = org - point (with org on a sphere around the "
    "point, a panorama seen from the surface).",
    kAwayFromParams, create_away_from};

}  // namespace anamorph
