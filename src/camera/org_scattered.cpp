#include "camera/org_scattered.h"

#include "camera/org_common.h"
#include "camera/scattered_common.h"

namespace anamorph {

namespace {

class ScatteredOrg final : public OrgFunctionLoop<ScatteredOrg> {
 public:
  ScatteredOrg(Rbf<2> rbf, bool flip) : rbf_(std::move(rbf)), flip_(flip) {}
  bool eval(Vec2 uv, SurfaceSample* out) const override {
    Vec3 g[2], h[3];
    const Vec3 p = rbf_.eval({uv.x, uv.y}, g, h);
    const LocalGeom geom{p, g[0], g[1], h[0], h[1], h[2]};
    set_position(geom, 1, 1, out);
    set_cross_normal(geom, 1, 1, flip_, out);
    return true;
  }
  // Only p and its first derivatives (a direction that reads no normal): no Hessian.
  void eval_batch_first_order(const double* u, const double* v, int n,
                              SurfaceBatch* out) const override {
    for (int i = 0; i < n; ++i) {
      Vec3 g[2];
      SurfaceBatch::put(out->p, i, rbf_.eval({u[i], v[i]}, g));
      SurfaceBatch::put(out->dpdu, i, g[0]);
      SurfaceBatch::put(out->dpdv, i, g[1]);
      out->ok[i] = true;
    }
  }

 private:
  Rbf<2> rbf_;
  bool flip_;
};

const ParamSpec kParams[] = {
    {"points", ParamType::NumberGrid, "",
     "The data: one [u, v, x, y, z] per point, the surface point (x, y, z) that image position "
     "(u, v) shows (u, v in [0, 1], u left to right, v top to bottom; camera space). Anywhere in "
     "the image, in any order (or up to 1e6 beyond it); no two at one (u, v), and with thin_plate "
     "or cubic not all on one line."},
    kRbfKernelParam,
    kRbfShapeParam,
    kRbfSmoothingParam,
    kFlipNormalParam,
};

std::unique_ptr<OrgFunction> create(const ParamValues& v) {
  check_params(kParams, v);
  const auto point = [](const ScatteredDatum& d, size_t) { return d.value; };
  return std::make_unique<ScatteredOrg>(planar_rbf(v, point), v.boolean("flip_normal"));
}

}  // namespace

const OrgFunctionInfo kScatteredOrgInfo{
    "scattered",
    "A smooth surface through control points placed anywhere in the image (the paper's scattered "
    "data interpolation, for control points not on a grid): radial basis interpolation "
    "S(u,v) = sum_i w_i phi(|(u,v) - (u_i,v_i)|) + p(u,v) of [u, v, x, y, z] points, solved once "
    "at load. Exact first and second derivatives, so dir = normal, ray differentials, coins, the "
    "inverse map and adaptive sampling work as on the spline surfaces.",
    kParams, create};

}  // namespace anamorph
