// Direction functions: constant and from_surface.
#include "camera/dir_basic.h"

namespace anamorph {

namespace {

class ConstantDir final : public DirFunction {
 public:
  explicit ConstantDir(Vec3 d) : d_(d) {}
  bool eval(Vec2, const SurfaceSample&, DirSample* out) const override {
    *out = DirSample{d_, {}, {}};
    return true;
  }

 private:
  Vec3 d_;
};

class SurfaceDir final : public DirFunction {
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

const ParamSpec kConstantParams[] = {
    {"direction", ParamType::Vec3, "[0, 0, -1]", "The direction of every ray (need not be unit)."},
};

const ParamSpec kFromSurfaceParams[] = {
    {"surface", ParamType::Function, "", "Any origin function, e.g. { type = \"sphere\", ... }."},
    {"center", ParamType::Vec3, "[0, 0, 0]",
     "The coordinate center c: dir(u,v) = S(u,v) - c (the paper's sphere function for dir)."},
};

std::unique_ptr<DirFunction> create_constant(const ParamValues& v) {
  const Vec3 d = v.vec3("direction");
  if (!(length(d) > 0)) throw ParamError("direction", "direction must not be zero");
  return make_constant_dir(d);
}

std::unique_ptr<DirFunction> create_from_surface(const ParamValues& v) {
  const NestedFunction& f = v.function("surface");
  const OrgFunctionInfo* info = find_org_function(f.type);
  if (!info) throw ParamError("surface", "unknown surface type '" + f.type + "'");
  return make_surface_dir(info->create(f.values), v.vec3("center"));
}

}  // namespace

std::unique_ptr<DirFunction> make_constant_dir(Vec3 d) { return std::make_unique<ConstantDir>(d); }
std::unique_ptr<DirFunction> make_surface_dir(std::unique_ptr<OrgFunction> s, Vec3 c) {
  return std::make_unique<SurfaceDir>(std::move(s), c);
}

const DirFunctionInfo kConstantDirInfo{
    "constant", "Every ray has the same direction (parallel projection with a plane org).",
    kConstantParams, create_constant};
const DirFunctionInfo kFromSurfaceDirInfo{
    "from_surface",
    "Directions from a surface: dir(u,v) = S(u,v) - center. A plane gives perspective with org point.",
    kFromSurfaceParams, create_from_surface};

}  // namespace anamorph
