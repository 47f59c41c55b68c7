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

namespace anamorph {

namespace {

struct OdsGeometry {
  AngleRange lon, lat;
  double half_ipd = 0.032;
  bool merge = false;
  double merge_a = 0, merge_b = 0;  // radians
  bool side_by_side = false;

  // Eye sign (-1 left, +1 right) and position inside that eye's image.
  int eye(Vec2 uv, Vec2* local, Vec2* scale) const {
    if (side_by_side) {
      const bool right = uv.x >= 0.5;
      *local = {right ? 2 * uv.x - 1 : 2 * uv.x, uv.y};
      *scale = {2, 1};
      return right ? 1 : -1;
    }
    const bool right = uv.y >= 0.5;
    *local = {uv.x, right ? 2 * uv.y - 1 : 2 * uv.y};
    *scale = {1, 2};
    return right ? 1 : -1;
  }
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

class OdsOrg final : public OrgFunction {
 public:
  explicit OdsOrg(const OdsGeometry& g) : g_(g) {}
  bool eval(Vec2 uv, SurfaceSample* out) const override {
    clear(out);
    Vec2 st, sc;
    const double s = g_.eye(uv, &st, &sc);
    const double lon = g_.longitude(st.x), lat = g_.latitude(st.y);
    const double lu = g_.lon.span() * sc.x, lv = -g_.lat.span() * sc.y;  // dlon/du, dlat/dv
    double m1, m2;
    const double R = s * g_.half_ipd * g_.merge_factor(lat, &m1, &m2);
    const double Rv = s * g_.half_ipd * m1 * lv, Rvv = s * g_.half_ipd * m2 * lv * lv;
    double sl, cl;
    sincos_poly(lon, &sl, &cl);
    const Vec3 radial{cl, 0, sl}, tangent{-sl, 0, cl};
    out->p = radial * R;
    out->dpdu = tangent * (R * lu);
    out->dpdv = radial * Rv;
    out->dpduu = radial * (-R * lu * lu);
    out->dpduv = tangent * (Rv * lu);
    out->dpdvv = radial * Rvv;
    return true;
  }

 private:
  OdsGeometry g_;
};

class OdsDir final : public DirFunction {
 public:
  explicit OdsDir(const OdsGeometry& g) : g_(g) {}
  bool eval(Vec2 uv, const SurfaceSample&, DirSample* out) const override {
    Vec2 st, sc;
    g_.eye(uv, &st, &sc);
    const double lon = g_.longitude(st.x), lat = g_.latitude(st.y);
    const double lu = g_.lon.span() * sc.x, lv = -g_.lat.span() * sc.y;
    double sl, cl, sp, cp;
    sincos_poly(lon, &sl, &cl);
    sincos_poly(lat, &sp, &cp);
    out->d = {sl * cp, sp, -cl * cp};
    out->dd_du = Vec3{cl * cp, 0, sl * cp} * lu;
    out->dd_dv = Vec3{-sl * sp, cp, cl * sp} * lv;
    return true;
  }

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
    {"ipd", ParamType::Number, "0.064",
     "Interpupillary distance in world units (the diameter of the eye circle).", 0, kInf},
    {"pole_merge", ParamType::Vec2, "none",
     "[a, b] in degrees, 0 <= a < b <= 90: the eye separation shrinks smoothly from ipd at "
     "|latitude| = a to 0 at b. Default: no merging.",
     0, 90},
    {"layout", ParamType::String, "\"over_under\"",
     "\"over_under\": left eye in the top half; \"side_by_side\": left eye in the left half.",
     -kInf, kInf, kLayouts},
    {"longitude_range", ParamType::Vec2, "[-180, 180]",
     "Longitudes in degrees at the left and right edges of each eye's image ([-90, 90] for "
     "VR180).",
     -720, 720},
    {"latitude_range", ParamType::Vec2, "[-90, 90]",
     "Latitudes in degrees at the bottom and top edges of each eye's image.", -90, 90},
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
