// Expression direction: three formulas in u, v, the origin (ox, oy, oz) and the normal
// (nx, ny, nz). Derivatives by central differences along the path the origin sample takes: a
// step h in u moves the origin by h dp/du and the normal by h dn/du.
#include "camera/dir_expression.h"

#include <cmath>

#include "camera/org_common.h"
#include "camera/org_expression.h"

namespace anamorph {

namespace {

class ExpressionDir final : public DirFunctionLoop<ExpressionDir> {
 public:
  ExpressionDir(std::unique_ptr<ExpressionSet> f, ParamRange ur, ParamRange vr)
      : f_(std::move(f)), ur_(ur), vr_(vr) {}

  bool eval(Vec2 uv, const SurfaceSample& o, DirSample* out) const override {
    constexpr double h = 1e-5;  // in image units; first derivatives only
    const auto at = [&](double du, double dv) {
      const Vec3 p = o.p + o.dpdu * du + o.dpdv * dv, n = o.n + o.dndu * du + o.dndv * dv;
      const double x[8] = {ur_(uv.x + du), vr_(uv.y + dv), p.x, p.y, p.z, n.x, n.y, n.z};
      return f_->eval(x);
    };
    const Vec3 d = at(0, 0);
    if (!is_finite(d)) return false;
    *out = DirSample{d, (at(h, 0) - at(-h, 0)) / (2 * h), (at(0, h) - at(0, -h)) / (2 * h)};
    return true;
  }

 private:
  std::unique_ptr<ExpressionSet> f_;
  ParamRange ur_, vr_;
};

const ParamSpec kParams[] = {
    {"x", ParamType::String, "",
     "Formula for the direction's x in u, v, ox, oy, oz (the origin), nx, ny, nz (its unit "
     "normal) and the constants (muParser syntax; `pi` is defined)."},
    {"y", ParamType::String, "", "Formula for the direction's y."},
    {"z", ParamType::String, "", "Formula for the direction's z."},
    {"constants", ParamType::StringMap, "{}", "Named constants, e.g. { k = 0.5 }."},
    {"u_range", ParamType::Vec2, "[0, 1]", "Values of u across the image, left to right."},
    {"v_range", ParamType::Vec2, "[0, 1]", "Values of v across the image, top to bottom."},
};

std::unique_ptr<DirFunction> create(const ParamValues& v) {
  check_params(kParams, v);
  auto f = std::make_unique<ExpressionSet>(
      std::vector<std::string>{"u", "v", "ox", "oy", "oz", "nx", "ny", "nz"},
      std::array<std::string, 3>{v.string("x"), v.string("y"), v.string("z")},
      std::array<std::string_view, 3>{"x", "y", "z"}, v.string_map("constants"));
  return std::make_unique<ExpressionDir>(std::move(f), read_range(v, "u_range"),
                                         read_range(v, "v_range"));
}

}  // namespace

const DirFunctionInfo kExpressionDirInfo{
    "expression",
    "A direction given by three formulas that may use u, v, the origin point (ox, oy, oz) and "
    "its normal (nx, ny, nz), e.g. a normal bent by position. Need not be unit length; no ray "
    "where a formula is not finite or the direction is zero.",
    kParams, create};

}  // namespace anamorph
