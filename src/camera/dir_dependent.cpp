// Dependent directions (the paper's "dependent vectors"): read from the origin sample, with ray
// differentials from its normal derivatives (dndu, dndv) and second derivatives.
#include "camera/dir_dependent.h"

#include <cmath>

#include "camera/org_common.h"
#include "math/simd.h"

namespace anamorph {

namespace {

// The normal fields of an origin batch as directions, scaled by s (1 or -1): compiled for several
// ISAs (math/simd.h), as the baseline build would copy them 16 bytes at a time.
ANAMORPH_KERNEL_BODY void scaled_normals_body(const SurfaceBatch& o, double s, int n,
                                              DirBatch* out) {
  with_trip_count<kCameraBatch>(
      n, [&](auto m) __attribute__((always_inline)) {
        for (int c = 0; c < 3; ++c)
          for (int i = 0; i < m; ++i) {
            out->d[c][i] = o.n[c][i] * s;
            out->du[c][i] = o.dndu[c][i] * s;
            out->dv[c][i] = o.dndv[c][i] * s;
          }
        for (int i = 0; i < m; ++i) out->ok[i] = true;
      });
}
constexpr simd::Kernel<scaled_normals_body> scaled_normals;

class NormalDir final : public DirFunction {
 public:
  explicit NormalDir(bool flip) : s_(flip ? -1.0 : 1.0) {}
  bool eval(Vec2, const SurfaceSample& o, DirSample* out) const override {
    *out = DirSample{o.n * s_, o.dndu * s_, o.dndv * s_};
    return true;  // a surface without normal (a point) gives a zero direction: no ray
  }
  void eval_batch(const double*, const double*, int n, const SurfaceBatch& o,
                  DirBatch* out) const override {
    scaled_normals(o, s_, n, out);
  }
  bool unit_length() const override { return true; }  // the unit normal (zero: no ray)

 private:
  double s_;
};

class TangentDir final : public DirFunctionLoop<TangentDir> {
 public:
  TangentDir(bool along_v, bool flip) : v_(along_v), s_(flip ? -1.0 : 1.0) {}
  bool eval(Vec2, const SurfaceSample& o, DirSample* out) const override {
    if (v_)
      *out = DirSample{o.dpdv * s_, o.dpduv * s_, o.dpdvv * s_};
    else
      *out = DirSample{o.dpdu * s_, o.dpduu * s_, o.dpduv * s_};
    return true;
  }

 private:
  bool v_;
  double s_;
};

// d = cos(a) n + sin(a) (cos(b) t1 + sin(b) t2) with t1 the unit u tangent (image right) and t2
// the unit tangent toward image up (-v), both perpendicular to n: the angle to the normal is
// exactly a, and the azimuth b turns counterclockwise as seen in the image.
class DeviatedNormalDir final : public DirFunctionLoop<DeviatedNormalDir> {
 public:
  DeviatedNormalDir(double angle, double azimuth, bool flip)
      : ca_(std::cos(angle)),
        sa_(std::sin(angle)),
        cb_(std::cos(azimuth)),
        sb_(std::sin(azimuth)),
        s_(flip ? -1.0 : 1.0) {}

  bool eval(Vec2, const SurfaceSample& o, DirSample* out) const override {
    const Vec3 n = o.n * s_, nu = o.dndu * s_, nv = o.dndv * s_;
    if (!(length_squared(n) > 0)) return false;
    if (sa_ == 0) {
      *out = DirSample{n * ca_, nu * ca_, nv * ca_};
      return true;
    }
    // t1 = unit(T), T = pu - n (n . pu); derivative along x in {u, v}.
    const Vec3 T = o.dpdu - n * dot(n, o.dpdu);
    const double lt = length(T);
    if (!(lt > 1e-300)) return false;  // u tangent degenerate (e.g. exactly at a pole)
    const Vec3 t1 = T / lt;
    const auto t1_d = [&](const Vec3& nx, const Vec3& pux) {
      const Vec3 Tx = pux - nx * dot(n, o.dpdu) - n * (dot(nx, o.dpdu) + dot(n, pux));
      return (Tx - t1 * dot(t1, Tx)) / lt;
    };
    const Vec3 t1u = t1_d(nu, o.dpduu), t1v = t1_d(nv, o.dpduv);
    // t2 = -unit(W), W = pv minus its components along n and t1.
    const Vec3 W = o.dpdv - n * dot(n, o.dpdv) - t1 * dot(t1, o.dpdv);
    const double lw = length(W);
    if (!(lw > 1e-300)) return false;
    const Vec3 w = W / lw;
    const auto t2_d = [&](const Vec3& nx, const Vec3& t1x, const Vec3& pvx) {
      const Vec3 Wx = pvx - nx * dot(n, o.dpdv) - n * (dot(nx, o.dpdv) + dot(n, pvx)) -
                      t1x * dot(t1, o.dpdv) - t1 * (dot(t1x, o.dpdv) + dot(t1, pvx));
      return -(Wx - w * dot(w, Wx)) / lw;
    };
    const Vec3 t2 = -w, t2u = t2_d(nu, t1u, o.dpduv), t2v = t2_d(nv, t1v, o.dpdvv);
    const auto mix = [&](const Vec3& a, const Vec3& b, const Vec3& c) {
      return a * ca_ + (b * cb_ + c * sb_) * sa_;
    };
    *out = DirSample{mix(n, t1, t2), mix(nu, t1u, t2u), mix(nv, t1v, t2v)};
    return true;
  }

 private:
  double ca_, sa_, cb_, sb_, s_;
};

const ParamSpec kNormalParams[] = {
    {"flip", ParamType::Bool, "false",
     "Use the reversed normal (look to the other side, e.g. inward from a sphere)."},
};
const ParamSpec kTangentUParams[] = {
    {"flip", ParamType::Bool, "false", "Use -dp/du (toward the image's left) instead."},
};
const ParamSpec kTangentVParams[] = {
    {"flip", ParamType::Bool, "false", "Use -dp/dv (toward the image's top) instead."},
};
const ParamSpec kDeviatedParams[] = {
    {.name = "angle",
     .type = ParamType::Number,
     .default_value = "0",
     .doc = "Angle between the ray and the normal, degrees.",
     .min = 0,
     .max = 180,
     .unit = "degrees"},
    {.name = "azimuth",
     .type = ParamType::Number,
     .default_value = "0",
     .doc = "Direction of the tilt around the normal, degrees: 0 toward increasing u (image "
            "right), 90 "
            "toward decreasing v (image up), counterclockwise as seen in the image.",
     .unit = "degrees"},
    {"flip", ParamType::Bool, "false", "Deviate from the reversed normal instead."},
};

std::unique_ptr<DirFunction> create_normal(const ParamValues& v) {
  check_params(kNormalParams, v);
  return make_normal_dir(v.boolean("flip"));
}
std::unique_ptr<DirFunction> create_tangent_u(const ParamValues& v) {
  check_params(kTangentUParams, v);
  return std::make_unique<TangentDir>(false, v.boolean("flip"));
}
std::unique_ptr<DirFunction> create_tangent_v(const ParamValues& v) {
  check_params(kTangentVParams, v);
  return std::make_unique<TangentDir>(true, v.boolean("flip"));
}
std::unique_ptr<DirFunction> create_deviated(const ParamValues& v) {
  check_params(kDeviatedParams, v);
  return std::make_unique<DeviatedNormalDir>(radians(v.number("angle")),
                                             radians(v.number("azimuth")), v.boolean("flip"));
}

}  // namespace

std::unique_ptr<DirFunction> make_normal_dir(bool flip) {
  return std::make_unique<NormalDir>(flip);
}

const DirFunctionInfo kNormalDirInfo{
    "normal",
    "The origin surface's unit normal at (u, v) (outward for closed surfaces, dp/du x dp/dv for "
    "open ones). With org plane a parallel projection; with org cylinder the cylinder "
    "projections of cartography; with org sphere an equirectangular panorama. No ray where the "
    "origin has no normal (org point).",
    kNormalParams, create_normal};
const DirFunctionInfo kTangentUDirInfo{
    "tangent_u",
    "The origin surface's tangent dp/du: rays run along the surface in the direction the "
    "origin moves as u increases (toward the image's right). No ray where it vanishes.",
    kTangentUParams, create_tangent_u};
const DirFunctionInfo kTangentVDirInfo{
    "tangent_v",
    "The origin surface's tangent dp/dv: rays run along the surface in the direction the "
    "origin moves as v increases (toward the image's bottom). No ray where it vanishes.",
    kTangentVParams, create_tangent_v};
const DirFunctionInfo kDeviatedNormalDirInfo{
    "deviated_normal",
    "The normal tilted by a constant angle toward a constant azimuth in the tangent plane (u "
    "tangent = azimuth 0, image up = 90). With org plane, still a parallel (oblique) "
    "projection.",
    kDeviatedParams, create_deviated};

}  // namespace anamorph
