// ods: omnidirectional stereo for VR (Peleg et al. 2001; Google's "Rendering Omni-directional
// Stereo Content"). Two equirectangular images, one per eye, over-under (left eye on top) or
// side by side (left eye on the left). For longitude lon and latitude lat:
//   org = s(eye) R(lat) (cos lon, 0, sin lon),   s = -1 left, +1 right, R = ipd/2 * m(lat),
//   dir = (sin lon cos lat, sin lat, -cos lon cos lat),
// so each eye's origins lie on a horizontal circle of radius ipd/2 and every ray is tangent to
// it (org . dir = 0); the left eye's circle point is the right eye's mirrored through the
// center. m(lat) is 1, or, with pole_merge = [a, b], falls smoothly (smoothstep) from 1 at
// |lat| = a to 0 at |lat| = b, so both eyes meet at the poles and the zenith and nadir show no
// stereo swirl.
// org = OdsOrg (the circle), dir = OdsDir (the unit sphere per eye).
#include <cmath>

#include "camera/preset_list.h"
#include "camera/preset_util.h"
#include "math/fast_trig.h"
#include "math/simd.h"

namespace anamorph {

namespace {

struct OdsGeometry {
  AngleRange lon, lat;
  double half_ipd = 0.032;
  bool merge = false;
  double merge_a = 0, merge_b = 0;  // radians
  bool side_by_side = false;

  double longitude(double s) const { return lon.lo + lon.span() * s; }
  double latitude(double t) const { return lat.hi - lat.span() * t; }

  // Radius factor m(lat) and its first two derivatives with respect to lat.
  double merge_factor(double phi, double* d1, double* d2) const {
    *d1 = *d2 = 0;
    if (!merge) return 1;
    const double a = std::abs(phi), sign = phi < 0 ? -1 : 1;
    if (a <= merge_a) return 1;
    if (a >= merge_b) return 0;
    const double w = merge_b - merge_a, x = (a - merge_a) / w;
    *d1 = -sign * 6 * x * (1 - x) / w;
    *d2 = -6 * (1 - 2 * x) / (w * w);
    return 1 - x * x * (3 - 2 * x);
  }
};

// One lane of ODS geometry as straight-line code (selects for the eye and the pole merge), so
// that batches vectorize; OdsOrg and OdsDir evaluate single samples as batches of one.
struct OdsLane {
  double lon, lat, lu, lv;  // angles and their derivatives d lon/du, d lat/dv
  double s;                 // eye sign: -1 left, +1 right
  double m, m1, m2;         // merge factor and its derivatives with respect to lat
};

// The layout is a template parameter and the logic bitwise: branches (also on a loop-invariant
// flag) would keep the loops that inline this scalar.
template <bool sbs>
[[gnu::always_inline]] inline OdsLane ods_lane(const OdsGeometry& g, double u, double v) {
  OdsLane l;
  const bool right = sbs ? u >= 0.5 : v >= 0.5;
  // Selects on constants only: a subtraction under a select would stay a branch (it may trap).
  const double half = right ? 1.0 : 0.0;
  const double x = sbs ? 2 * u - half : u;
  const double y = sbs ? v : 2 * v - half;
  const double scx = sbs ? 2.0 : 1.0, scy = sbs ? 1.0 : 2.0;
  l.s = right ? 1.0 : -1.0;
  l.lon = g.lon.lo + g.lon.span() * x;
  l.lat = g.lat.hi - g.lat.span() * y;
  l.lu = g.lon.span() * scx;
  l.lv = -g.lat.span() * scy;
  // merge_factor(): 1 up to merge_a, 0 from merge_b, a smoothstep between.
  const double a = l.lat < 0 ? -l.lat : l.lat, sign = l.lat < 0 ? -1.0 : 1.0;
  // Multiplications by 1/w: a division inside a select would stay a branch (it may trap).
  const double w = g.merge_b - g.merge_a, iw = 1 / w, t = (a - g.merge_a) * iw;
  const bool between = g.merge & (a > g.merge_a) & (a < g.merge_b);
  l.m = (!g.merge | (a <= g.merge_a)) ? 1.0 : (a >= g.merge_b ? 0.0 : 1 - t * t * (3 - 2 * t));
  l.m1 = between ? -sign * 6 * t * (1 - t) * iw : 0.0;
  l.m2 = between ? -6 * (1 - 2 * t) * (iw * iw) : 0.0;
  return l;
}

// kFirstOrder: p, dpdu, dpdv and ok only (OrgFunction::eval_batch_first_order).
template <bool sbs, bool kFirstOrder>
[[gnu::always_inline]] inline void ods_org_kernel(const OdsGeometry& geo,
                                                  const double* __restrict u,
                                                  const double* __restrict v, int n,
                                                  SurfaceBatch* __restrict out) {
  const OdsGeometry g = geo;
  constexpr int N = kCameraBatch;
  alignas(64) double sl[N], cl[N], R[N], Rv[N], Rvv[N], lu[N];
  for (int i = 0; i < n; ++i) {
    const OdsLane l = ods_lane<sbs>(g, u[i], v[i]);
    R[i] = l.s * g.half_ipd * l.m;
    Rv[i] = l.s * g.half_ipd * l.m1 * l.lv;
    Rvv[i] = l.s * g.half_ipd * l.m2 * l.lv * l.lv;
    lu[i] = l.lu;
    sincos_poly(l.lon, &sl[i], &cl[i]);
  }
  for (int i = 0; i < n; ++i) {
    const double c = cl[i], s = sl[i], r = R[i], ru = R[i] * lu[i];
    // radial (c, 0, s), tangent (-s, 0, c); the normal fields stay zero.
    out->p[0][i] = c * r, out->p[1][i] = 0, out->p[2][i] = s * r;
    out->dpdu[0][i] = -s * ru, out->dpdu[1][i] = 0, out->dpdu[2][i] = c * ru;
    out->dpdv[0][i] = c * Rv[i], out->dpdv[1][i] = 0, out->dpdv[2][i] = s * Rv[i];
    if (kFirstOrder) continue;
    const double ruu = -R[i] * lu[i] * lu[i], ruv = Rv[i] * lu[i];
    out->dpduu[0][i] = c * ruu, out->dpduu[1][i] = 0, out->dpduu[2][i] = s * ruu;
    out->dpduv[0][i] = -s * ruv, out->dpduv[1][i] = 0, out->dpduv[2][i] = c * ruv;
    out->dpdvv[0][i] = c * Rvv[i], out->dpdvv[1][i] = 0, out->dpdvv[2][i] = s * Rvv[i];
    for (int k = 0; k < 3; ++k) out->n[k][i] = out->dndu[k][i] = out->dndv[k][i] = 0;
  }
  for (int i = 0; i < n; ++i) out->ok[i] = true;
}

template <bool kFirstOrder>
[[gnu::always_inline]] inline void ods_orgs_any_layout(const OdsGeometry& g, const double* u,
                                                       const double* v, int n, SurfaceBatch* out) {
  with_trip_count<kCameraBatch>(
      n, [&](auto m) __attribute__((always_inline)) {
        if (g.side_by_side)
          ods_org_kernel<true, kFirstOrder>(g, u, v, m, out);
        else
          ods_org_kernel<false, kFirstOrder>(g, u, v, m, out);
      });
}
ANAMORPH_KERNEL_BODY void ods_orgs_body(const OdsGeometry& g, bool first_order, const double* u,
                                        const double* v, int n, SurfaceBatch* out) {
  if (first_order)
    ods_orgs_any_layout<true>(g, u, v, n, out);
  else
    ods_orgs_any_layout<false>(g, u, v, n, out);
}
constexpr simd::Kernel<ods_orgs_body> ods_orgs;

template <bool sbs>
[[gnu::always_inline]] inline void ods_dir_kernel(const OdsGeometry& geo,
                                                  const double* __restrict u,
                                                  const double* __restrict v, int n,
                                                  DirBatch* __restrict out) {
  const OdsGeometry g = geo;
  for (int i = 0; i < n; ++i) {
    const OdsLane l = ods_lane<sbs>(g, u[i], v[i]);
    double sl, cl, sp, cp;
    sincos_poly(l.lon, &sl, &cl);
    sincos_poly(l.lat, &sp, &cp);
    out->d[0][i] = sl * cp, out->d[1][i] = sp, out->d[2][i] = -cl * cp;
    out->du[0][i] = cl * cp * l.lu, out->du[1][i] = 0, out->du[2][i] = sl * cp * l.lu;
    out->dv[0][i] = -sl * sp * l.lv, out->dv[1][i] = cp * l.lv, out->dv[2][i] = cl * sp * l.lv;
  }
  for (int i = 0; i < n; ++i) out->ok[i] = true;
}

ANAMORPH_KERNEL_BODY void ods_dirs_body(const OdsGeometry& g, const double* u, const double* v,
                                        int n, DirBatch* out) {
  with_trip_count<kCameraBatch>(
      n, [&](auto m) __attribute__((always_inline)) {
        if (g.side_by_side)
          ods_dir_kernel<true>(g, u, v, m, out);
        else
          ods_dir_kernel<false>(g, u, v, m, out);
      });
}
constexpr simd::Kernel<ods_dirs_body> ods_dirs;

class OdsOrg final : public OrgFunction {
 public:
  explicit OdsOrg(const OdsGeometry& g) : g_(g) {}
  bool eval(Vec2 uv, SurfaceSample* out) const override {
    return eval_as_batch_of_one(*this, uv, out);
  }
  void eval_batch(const double* u, const double* v, int n, SurfaceBatch* out) const override {
    ods_orgs(g_, false, u, v, n, out);
  }
  void eval_batch_first_order(const double* u, const double* v, int n,
                              SurfaceBatch* out) const override {
    ods_orgs(g_, true, u, v, n, out);
  }

 private:
  OdsGeometry g_;
};

class OdsDir final : public DirFunction {
 public:
  explicit OdsDir(const OdsGeometry& g) : g_(g) {}
  bool eval(Vec2 uv, const SurfaceSample& org, DirSample* out) const override {
    return eval_as_batch_of_one(*this, uv, org, out);
  }
  void eval_batch(const double* u, const double* v, int n, const SurfaceBatch&,
                  DirBatch* out) const override {
    ods_dirs(g_, u, v, n, out);
  }
  bool unit_length() const override { return true; }  // a point of the unit sphere
  bool reads_org_beyond_first_order() const override { return false; }  // reads none of it

 private:
  OdsGeometry g_;
};

// The inverse per eye: with the point at horizontal distance rho and azimuth alpha (x, z),
// tangency gives rho cos(lon - alpha) = s R, the ray ahead gives lon = alpha + acos(s R / rho),
// and the elevation over the horizontal run sqrt(rho^2 - R^2) gives tan(lat). With pole merging
// R depends on lat: lat is the fixed point of that relation, found by bisection.
std::vector<Vec2> ods_project(const OdsGeometry& g, const Vec3& q) {
  const double rho = std::sqrt(q.x * q.x + q.z * q.z);
  const double alpha = std::atan2(q.z, q.x);
  std::vector<Vec2> out;
  for (int s : {-1, 1}) {
    double d1, d2;
    const auto radius = [&](double lat) { return g.half_ipd * g.merge_factor(lat, &d1, &d2); };
    // f(lat) = atan2(y, sqrt(rho^2 - R(lat)^2)) - lat decreases in lat.
    const auto f = [&](double lat) {
      const double R = radius(lat);
      return std::atan2(q.y, std::sqrt(std::max(rho * rho - R * R, 0.0))) - lat;
    };
    double lat;
    if (!g.merge) {
      lat = f(0);
    } else {
      double lo = -kPi / 2, hi = kPi / 2;
      for (int i = 0; i < 200 && hi - lo > 1e-16; ++i) {
        const double m = 0.5 * (lo + hi);
        (f(m) > 0 ? lo : hi) = m;
      }
      lat = 0.5 * (lo + hi);
    }
    const double R = radius(lat);
    if (!(rho > R) && !(R == 0 && length(q) > 0)) continue;  // inside the circle: not seen
    const double lon = R > 0 ? alpha + std::acos(s * R / rho) : std::atan2(q.x, -q.z);
    const double v = (g.lat.hi - lat) / g.lat.span();
    if (!(v >= -1e-9 && v <= 1 + 1e-9)) continue;
    double us[3];
    const int n = longitude_to_u(std::remainder(lon, 2 * kPi), g.lon, us);
    for (int i = 0; i < n; ++i) {
      const Vec2 st{us[i], std::clamp(v, 0.0, 1.0)};
      const bool right = s > 0;
      out.push_back(g.side_by_side ? Vec2{(st.x + (right ? 1 : 0)) / 2, st.y}
                                   : Vec2{st.x, (st.y + (right ? 1 : 0)) / 2});
    }
  }
  return out;
}

const std::string_view kLayouts[] = {"over_under", "side_by_side"};

const ParamSpec kParams[] = {
    ANAMORPH_LOOK_AT_PARAMS,
    {.name = "ipd",
     .type = ParamType::Number,
     .default_value = "0.064",
     .doc = "Interpupillary distance in world units (the diameter of the eye circle).",
     .min = 0,
     .unit = "scene units"},
    {.name = "pole_merge",
     .type = ParamType::Vec2,
     .default_value = "none",
     .doc = "[a, b] in degrees, 0 <= a < b <= 90: the eye separation shrinks smoothly from ipd at "
            "|latitude| = a to 0 at b. Default: no merging.",
     .min = 0,
     .max = 90,
     .unit = "degrees"},
    {"layout", ParamType::String, "\"over_under\"",
     "\"over_under\": left eye in the top half; \"side_by_side\": left eye in the left half.",
     -kInf, kInf, kLayouts},
    {.name = "longitude_range",
     .type = ParamType::Vec2,
     .default_value = "[-180, 180]",
     .doc = "Longitudes in degrees at the left and right edges of each eye's image ([-90, 90] for "
            "VR180).",
     .min = -720,
     .max = 720,
     .unit = "degrees"},
    {.name = "latitude_range",
     .type = ParamType::Vec2,
     .default_value = "[-90, 90]",
     .doc = "Latitudes in degrees at the bottom and top edges of each eye's image.",
     .min = -90,
     .max = 90,
     .unit = "degrees"},
};

VirtualCameraParts create(const ParamValues& v, const ImageInfo&) {
  check_params(kParams, v);
  OdsGeometry g;
  g.lon = read_angle_range(v, "longitude_range", 180);
  g.lat = read_angle_range(v, "latitude_range", 90);
  g.half_ipd = v.number("ipd") / 2;
  g.side_by_side = v.string("layout") == "side_by_side";
  if (v.has("pole_merge")) {
    const Vec2 m = v.vec2("pole_merge");
    if (!(m.x < m.y)) throw ParamError("pole_merge", "pole_merge must be [a, b] with a < b");
    g.merge = true;
    g.merge_a = radians(m.x), g.merge_b = radians(m.y);
  }
  VirtualCameraParts p;
  p.org = std::make_unique<OdsOrg>(g);
  p.dir = std::make_unique<OdsDir>(g);
  p.world_from_camera = rig_from_look_at(v);
  p.description = "ods " + v.string("layout") + " (org eye circle + dir sphere per eye)";
  p.inverse = make_inverse([g](const Vec3& q) { return ods_project(g, q); });
  return p;
}

}  // namespace

const PresetInfo kOdsPreset{
    "ods",
    "Omnidirectional stereo: one equirectangular image per eye, origins on a circle of radius "
    "ipd/2 with rays tangent to it. org = eye circle, dir = sphere.",
    kParams, create};

}  // namespace anamorph
