// The fisheye family: fisheye, mirror_ball and dome. All three are org = point (the eye) and
// dir = FisheyeDir, the points of a sphere laid out by a radial mapping theta(r) around an axis:
// dir(u,v) = radius * s(theta(r), azimuth) - eye. For fisheye and mirror_ball the sphere is the
// unit sphere around the eye; for dome it is the dome itself and the eye may sit off its center
// (the paper's "org: point, dir: sphere, not concentric").
#include <array>
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "camera/org_basic.h"
#include "camera/preset_list.h"
#include "camera/preset_util.h"
#include "math/fast_trig.h"
#include "math/simd.h"

namespace anamorph {

namespace {

// The most polynomial coefficients (degree 23): more than any lens model uses (Kannala-Brandt
// goes to r^9, Scaramuzza's to about r^12), in a fixed array so the mapping copies cheaply.
constexpr size_t kMaxPolyTerms = 24;

// theta(r): the angle from the axis at normalized image radius r (r = 1 on the image circle).
struct FisheyeMapping {
  enum Kind { kEquidistant, kEquisolid, kStereographic, kOrthographic, kPolynomial };
  Kind kind = kEquidistant;
  double theta_max = kPi / 2;             // fov / 2
  std::array<double, kMaxPolyTerms> k{};  // polynomial coefficients, radians
  int terms = 0;                          // how many of k are used

  double poly(double r, double* dtheta) const {
    double t = 0, dt = 0;
    for (int i = terms - 1; i >= 0; --i) {
      dt = dt * r + t;
      t = t * r + k[size_t(i)];
    }
    *dtheta = dt;
    return t;
  }

  double theta(double r, double* dtheta) const {
    *dtheta = 0;
    switch (kind) {
      case kEquidistant:
        *dtheta = theta_max;
        return r * theta_max;
      case kEquisolid: {  // r = sin(theta/2) / sin(theta_max/2)
        const double s = std::sin(theta_max / 2);
        *dtheta = 2 * s / std::sqrt(std::max(1 - r * r * s * s, 1e-24));
        return 2 * std::asin(std::min(r * s, 1.0));
      }
      case kStereographic: {  // r = tan(theta/2) / tan(theta_max/2)
        const double t = std::tan(theta_max / 2);
        *dtheta = 2 * t / (1 + r * r * t * t);
        return 2 * std::atan(r * t);
      }
      case kOrthographic: {  // r = sin(theta) / sin(theta_max)
        const double s = std::sin(theta_max);
        *dtheta = s / std::sqrt(std::max(1 - r * r * s * s, 1e-24));
        return std::asin(std::min(r * s, 1.0));
      }
      case kPolynomial:
        return poly(r, dtheta);
    }
    return 0;
  }

  // The image radius of angle theta; false when theta is outside the image circle.
  bool radius(double theta, double* r) const {
    constexpr double tol = 1e-12;
    *r = 0;
    switch (kind) {
      case kEquidistant:
        *r = theta / theta_max;
        break;
      case kEquisolid:
        *r = std::sin(theta / 2) / std::sin(theta_max / 2);
        break;
      case kStereographic:
        if (theta >= kPi) return false;
        *r = std::tan(theta / 2) / std::tan(theta_max / 2);
        break;
      case kOrthographic:
        if (theta > kPi / 2) return false;
        *r = std::sin(theta) / std::sin(theta_max);
        break;
      case kPolynomial: {
        // theta(r) increases on [0, 1] (checked at construction): safeguarded Newton.
        double d;
        const double t0 = poly(0, &d), t1 = poly(1, &d);
        if (theta < t0 - tol || theta > t1 + tol) return false;
        double lo = 0, hi = 1, x = (t1 > t0) ? (theta - t0) / (t1 - t0) : 0;
        for (int i = 0; i < 100; ++i) {
          const double f = poly(x, &d) - theta;
          if (f > 0)
            hi = x;
          else
            lo = x;
          if (std::abs(f) < 1e-15) break;
          double nx = x - f / d;
          if (!(nx > lo && nx < hi)) nx = 0.5 * (lo + hi);
          if (std::abs(nx - x) < 1e-16) break;
          x = nx;
        }
        *r = x;
        break;
      }
    }
    if (!(*r <= 1 + tol) || !(*r >= 0)) return false;
    *r = std::min(*r, 1.0);
    return true;
  }
};

// An orthonormal frame for the fisheye sphere: the axis (image center) and the directions that
// image right (+a) and image up (+b) lean towards.
struct FisheyeFrame {
  Vec3 right{1, 0, 0}, up{0, 1, 0}, axis{0, 0, -1};
  // Local radial_direction() vectors have the axis at -z.
  Vec3 to_camera(const Vec3& l) const { return right * l.x + up * l.y - axis * l.z; }
  Vec3 to_local(const Vec3& c) const { return {dot(c, right), dot(c, up), -dot(c, axis)}; }
};

// Image coordinates: a = (u - cu) sa, b = (cv - v) sb, so that r = |(a, b)| = 1 on the circle
// around (cu, cv).
struct FisheyeGeometry {
  FisheyeMapping map;
  FisheyeFrame frame;
  double sa = 2, sb = 2;
  double cu = 0.5, cv = 0.5;  // the image position of the circle's center
  // Cut-offs (no ray beyond them; the defaults cut nothing): cos of the largest angle from the
  // axis, and the sine of the lowest elevation above the plane perpendicular to `up_cam` (the
  // world's +y in camera space) of the unit direction from the eye.
  double cos_max_angle = -2, sin_min_elevation = -2;
  Vec3 up_cam{0, 1, 0};
  double radius = 1;  // of the sphere, around the camera-space origin
  Vec3 eye;           // the ray origin
  // sin(fov/4), tan(fov/4), sin(fov/2): set by FisheyeDir once, not per ray.
  double half_sin = 0, half_tan = 0, full_sin = 0;
};

// Whether direction d (from the eye, any length) rises at least to the minimum elevation.
inline bool above_min_elevation(const FisheyeGeometry& g, const Vec3& d) {
  return dot(d, g.up_cam) >= g.sin_min_elevation * length(d);
}

// The fisheye directions as straight-line code over a batch, which the compiler vectorizes
// (radial_lane for the direction). No inverse trigonometry: the
// mappings give sin(theta) and cos(theta) algebraically (equisolid from sin(theta/2), stereographic
// from tan(theta/2), orthographic from sin(theta)); equidistant uses sincos_poly. Lanes outside
// the image circle get ok = false. (The polynomial mapping stays on the one-at-a-time path.)
template <FisheyeMapping::Kind K>
[[gnu::always_inline]] inline void fisheye_kernel(const FisheyeGeometry& geo,
                                                  const double* __restrict u,
                                                  const double* __restrict v, int n,
                                                  DirBatch* __restrict out) {
  const FisheyeGeometry g = geo;  // a local copy: stores to `out` cannot alias it
  const double tm = g.map.theta_max, R = g.radius, su = R * g.sa, sv = -R * g.sb;
  const double half_sin = g.half_sin, half_tan = g.half_tan, full_sin = g.full_sin;
  const Vec3 X = g.frame.right, Y = g.frame.up, Z = g.frame.axis;
  alignas(64) double radius[kCameraBatch], cosine[kCameraBatch];
  for (int i = 0; i < n; ++i) {
    double a = (u[i] - g.cu) * g.sa, b = (g.cv - v[i]) * g.sb;
    const double r = std::sqrt(a * a + b * b);
    radius[i] = r;
    const double ik = 1 / (r > 1 ? r : 1.0);  // onto the circle (exactly 1 inside it)
    a *= ik, b *= ik;
    const double rc = r < 1 ? r : 1.0;
    double st, ct, dth;  // sin and cos of theta(rc), d theta / d r
    if constexpr (K == FisheyeMapping::kEquidistant) {
      sincos_poly(rc * tm, &st, &ct);
      dth = tm;
    } else if constexpr (K == FisheyeMapping::kEquisolid) {  // sin(theta/2) = r sin(tm/2)
      const double x0 = rc * half_sin, x = x0 < 1 ? x0 : 1.0, c = std::sqrt(1 - x * x);
      st = 2 * x * c, ct = 1 - 2 * x * x;
      const double q = 1 - rc * rc * half_sin * half_sin;
      dth = 2 * half_sin / std::sqrt(q > 1e-24 ? q : 1e-24);
    } else if constexpr (K == FisheyeMapping::kStereographic) {  // tan(theta/2) = r tan(tm/2)
      const double t = rc * half_tan, den = 1 / (1 + t * t);
      st = 2 * t * den, ct = (1 - t * t) * den;
      dth = 2 * half_tan * den;
    } else {  // orthographic: sin(theta) = r sin(tm)
      const double x0 = rc * full_sin, x = x0 < 1 ? x0 : 1.0;
      st = x, ct = std::sqrt(1 - x * x);
      const double q = 1 - rc * rc * full_sin * full_sin;
      dth = full_sin / std::sqrt(q > 1e-24 ? q : 1e-24);
    }
    bool axis;  // theta(0) = 0 for every mapping here: the axis has its direction
    const RadialDirection rd = radial_lane(a, b, st, ct, dth, &axis);
    const double lx = rd.d.x, ly = rd.d.y, lz = rd.d.z;
    const double ax = rd.dd_da.x, ay = rd.dd_da.y, az = rd.dd_da.z;
    const double bx = rd.dd_db.x, by = rd.dd_db.y, bz = rd.dd_db.z;
    // frame.to_camera(l) = right l.x + up l.y - axis l.z
    out->d[0][i] = (X.x * lx + Y.x * ly - Z.x * lz) * R - g.eye.x;
    out->d[1][i] = (X.y * lx + Y.y * ly - Z.y * lz) * R - g.eye.y;
    out->d[2][i] = (X.z * lx + Y.z * ly - Z.z * lz) * R - g.eye.z;
    out->du[0][i] = (X.x * ax + Y.x * ay - Z.x * az) * su;
    out->du[1][i] = (X.y * ax + Y.y * ay - Z.y * az) * su;
    out->du[2][i] = (X.z * ax + Y.z * ay - Z.z * az) * su;
    out->dv[0][i] = (X.x * bx + Y.x * by - Z.x * bz) * sv;
    out->dv[1][i] = (X.y * bx + Y.y * by - Z.y * bz) * sv;
    out->dv[2][i] = (X.z * bx + Y.z * by - Z.z * bz) * sv;
    cosine[i] = ct;
  }
  // Outside the image circle or beyond a cut-off: no ray. (A separate loop: bool stores keep the
  // one above scalar.)
  for (int i = 0; i < n; ++i)
    out->ok[i] = radius[i] <= 1 + 1e-12 && cosine[i] >= g.cos_max_angle &&
                 (g.sin_min_elevation < -1 || above_min_elevation(g, out->lane(i).d));
}

// Constant trip counts for full packets and for one-at-a-time calls: full vectors with no
// remainder loop, and straight-line code.
template <FisheyeMapping::Kind K>
[[gnu::always_inline]] inline void fisheye_run(const FisheyeGeometry& g, const double* u,
                                               const double* v, int n, DirBatch* out) {
  with_trip_count<kCameraBatch>(
      n, [&](auto m) __attribute__((always_inline)) { fisheye_kernel<K>(g, u, v, m, out); });
}

ANAMORPH_KERNEL_BODY void fisheye_dirs_body(const FisheyeGeometry& g, const double* u,
                                            const double* v, int n, DirBatch* out) {
  switch (g.map.kind) {
    case FisheyeMapping::kEquidistant:
      return fisheye_run<FisheyeMapping::kEquidistant>(g, u, v, n, out);
    case FisheyeMapping::kEquisolid:
      return fisheye_run<FisheyeMapping::kEquisolid>(g, u, v, n, out);
    case FisheyeMapping::kStereographic:
      return fisheye_run<FisheyeMapping::kStereographic>(g, u, v, n, out);
    case FisheyeMapping::kOrthographic:
      return fisheye_run<FisheyeMapping::kOrthographic>(g, u, v, n, out);
    case FisheyeMapping::kPolynomial:  // FisheyeDir keeps it on its one-at-a-time path
      return;
  }
}
constexpr simd::Kernel<fisheye_dirs_body> fisheye_dirs;

class FisheyeDir final : public DirFunction {
 public:
  explicit FisheyeDir(const FisheyeGeometry& g) : g_(g) {
    const double tm = g_.map.theta_max;
    g_.half_sin = std::sin(tm / 2), g_.half_tan = std::tan(tm / 2), g_.full_sin = std::sin(tm);
  }
  bool eval(Vec2 uv, const SurfaceSample& org, DirSample* out) const override {
    if (g_.map.kind != FisheyeMapping::kPolynomial) {
      return eval_as_batch_of_one(*this, uv, org, out);
    }
    double a = (uv.x - g_.cu) * g_.sa, b = (g_.cv - uv.y) * g_.sb;
    const double r = std::sqrt(a * a + b * b);
    if (!(r <= 1 + 1e-12)) return false;  // outside the image circle: no ray
    if (r > 1) a /= r, b /= r;
    double dtheta;
    const double theta = g_.map.theta(std::min(r, 1.0), &dtheta);
    if (std::cos(theta) < g_.cos_max_angle) return false;
    RadialDirection rd;
    if (!radial_direction(a, b, theta, dtheta, &rd)) return false;
    const double R = g_.radius;
    out->d = g_.frame.to_camera(rd.d) * R - g_.eye;
    out->dd_du = g_.frame.to_camera(rd.dd_da) * (R * g_.sa);
    out->dd_dv = g_.frame.to_camera(rd.dd_db) * (-R * g_.sb);
    return g_.sin_min_elevation < -1 || above_min_elevation(g_, out->d);
  }

  void eval_batch(const double* u, const double* v, int n, const SurfaceBatch& org,
                  DirBatch* out) const override {
    if (g_.map.kind == FisheyeMapping::kPolynomial)
      DirFunction::eval_batch(u, v, n, org, out);
    else
      fisheye_dirs(g_, u, v, n, out);
  }
  // The unit sphere around the eye (fisheye, mirror_ball), not a dome seen off its center.
  bool unit_length() const override { return g_.radius == 1 && g_.eye == Vec3{}; }

 private:
  FisheyeGeometry g_;
};

// Closed form: the sphere point on the eye's ray through q, then the mapping's inverse.
std::vector<Vec2> fisheye_project(const FisheyeGeometry& g, const Vec3& q) {
  const Vec3 w = q - g.eye;
  const double len = length(w);
  if (!(len > 0)) return {};
  const Vec3 wn = w / len;
  const double b = dot(g.eye, wn), c = dot(g.eye, g.eye) - g.radius * g.radius;
  const double disc = b * b - c;
  if (disc < 0) return {};
  const double t = -b + std::sqrt(disc);
  if (!(t > 0)) return {};
  Vec2 az;
  const double theta = polar_angle(g.frame.to_local(g.eye + wn * t), &az);
  double r;
  if (!g.map.radius(theta, &r)) return {};
  if (std::cos(theta) < g.cos_max_angle) return {};
  if (g.sin_min_elevation >= -1 && !above_min_elevation(g, wn)) return {};
  Vec2 uv{g.cu + r * az.x / g.sa, g.cv - r * az.y / g.sb};
  if (!clamp_to_image(&uv)) return {};
  return {uv};
}

VirtualCameraParts fisheye_parts(const FisheyeGeometry& g, const ParamValues& v,
                                 std::string description) {
  VirtualCameraParts p;
  p.org = make_point_org(g.eye);
  p.dir = std::make_unique<FisheyeDir>(g);
  p.world_from_camera = rig_from_look_at(v);
  p.derivatives.rig = look_at_rig_derivative(v);
  p.description = std::move(description);
  p.inverse = make_inverse([g](const Vec3& q) { return fisheye_project(g, q); });
  return p;
}

// Scale from (u, v) to image radius for a circle of `diameter` pixels.
void set_circle(FisheyeGeometry* g, const ImageInfo& img, double diameter) {
  g->sa = 2 * img.width / diameter;
  g->sb = 2 * img.height / diameter;
}

std::string fmt_deg(double rad) { return fmt::format("{:.10g}", degrees(rad)); }

// --- fisheye ---------------------------------------------------------------------------------

const std::string_view kMappings[] = {"equidistant", "equisolid", "stereographic", "orthographic",
                                      "polynomial"};
const std::string_view kFits[] = {"circle", "full_frame", "pixels", "omnimax"};

// POV-Ray's omnimax frame (its tracepixel.cpp): the circle spans the width up to this aspect
// ratio (width / height) and its top touches the image's top; wider frames keep this circle.
constexpr double kOmnimaxAspect = 1.283458;

const ParamSpec kFisheyeParams[] = {
    ANAMORPH_LOOK_AT_PARAMS,
    {.name = "fov",
     .type = ParamType::Number,
     .default_value = "180",
     .doc = "Field of view in degrees across the image circle (the edge of the circle is fov/2 "
            "from the "
            "axis). Up to 360; stereographic < 360, orthographic <= 180.",
     .min = 0,
     .max = 360,
     .min_exclusive = true,
     .unit = "degrees"},
    {"mapping", ParamType::String, "\"equidistant\"",
     "theta(r) for r in [0, 1]: equidistant theta = r fov/2; equisolid r = sin(theta/2) / "
     "sin(fov/4); stereographic r = tan(theta/2) / tan(fov/4); orthographic r = sin(theta) / "
     "sin(fov/2); polynomial theta = k0 + k1 r + k2 r^2 + ... (from `poly`, any degree up to "
     "23).",
     -kInf, kInf, kMappings},
    {"poly", ParamType::NumberList, "none",
     "Polynomial coefficients [k0, k1, ..., kn] in radians, n up to 23, for mapping = "
     "\"polynomial\". theta(r) must increase on [0, 1] and theta(1) must equal fov/2."},
    {"fit", ParamType::String, "\"circle\"",
     "Image circle diameter: \"circle\" = the shorter image side (the whole circle visible), "
     "\"full_frame\" = the image diagonal (the frame filled), \"pixels\" = circle_diameter, "
     "\"omnimax\" = POV-Ray's omnimax frame (diameter min(width, 1.283458 height), the circle's "
     "top at the image's top when the image is wider than tall, so the frame cuts its bottom; "
     "centered otherwise).",
     -kInf, kInf, kFits},
    {"circle_diameter",
     ParamType::Number,
     "none",
     "Diameter of the image circle in pixels, with fit = \"pixels\".",
     0,
     kInf,
     {},
     true},
    {"circle_center", ParamType::Vec2, "none",
     "The image position (u, v) of the circle's center, the axis (default: the image center; "
     "with fit = \"omnimax\" set by the fit)."},
    {.name = "max_angle",
     .type = ParamType::Number,
     .default_value = "none",
     .doc = "No ray beyond this angle from the axis (default: fov / 2, the circle's rim): a "
            "circular cut-off inside the image circle.",
     .min = 0,
     .max = 180,
     .unit = "degrees"},
    {.name = "min_elevation",
     .type = ParamType::Number,
     .default_value = "none",
     .doc = "No ray below this elevation above the horizon, the plane perpendicular to the "
            "world's +y as the look-at rig sees it (before camera.transform): e.g. 0 cuts "
            "everything below the horizon, -10 keeps 10 degrees of it, as a dome theatre's "
            "screen ends there.",
     .min = -90,
     .max = 90,
     .unit = "degrees"},
};

FisheyeMapping read_mapping(const ParamValues& v) {
  FisheyeMapping m;
  const double fov = v.number("fov");
  m.theta_max = radians(fov) / 2;
  const std::string& name = v.string("mapping");
  if (name == "equidistant")
    m.kind = FisheyeMapping::kEquidistant;
  else if (name == "equisolid")
    m.kind = FisheyeMapping::kEquisolid;
  else if (name == "stereographic")
    m.kind = FisheyeMapping::kStereographic;
  else if (name == "orthographic")
    m.kind = FisheyeMapping::kOrthographic;
  else
    m.kind = FisheyeMapping::kPolynomial;
  if (m.kind == FisheyeMapping::kStereographic && !(fov < 360))
    throw ParamError("fov", "fov must be < 360 with mapping = \"stereographic\"");
  if (m.kind == FisheyeMapping::kOrthographic && !(fov <= 180))
    throw ParamError("fov", "fov must be <= 180 with mapping = \"orthographic\"");
  if (m.kind != FisheyeMapping::kPolynomial) {
    if (v.has("poly")) throw ParamError("poly", "poly is only used with mapping = \"polynomial\"");
    return m;
  }
  if (!v.has("poly"))
    throw ParamError("mapping", "mapping = \"polynomial\" needs poly = [k0, k1, ...]");
  const auto& k = v.numbers("poly");
  if (k.empty() || k.size() > kMaxPolyTerms)
    throw ParamError("poly",
                     fmt::format("poly needs 1 to {} coefficients (degree up to {}), not {}",
                                 kMaxPolyTerms, kMaxPolyTerms - 1, k.size()));
  for (size_t i = 0; i < k.size(); ++i) m.k[i] = k[i];
  m.terms = int(k.size());
  double d;
  if (m.k[0] < 0) throw ParamError("poly", "theta(0) = k0 must be >= 0");
  for (int i = 0; i <= 1000; ++i) {
    m.poly(i / 1000.0, &d);
    if (!(d > 0))
      throw ParamError("poly", fmt::format("theta(r) must increase on [0, 1]; its slope is {:g} "
                                           "at r = {:g}",
                                           d, i / 1000.0));
  }
  const double t1 = m.poly(1, &d);
  if (t1 > kPi + 1e-12) throw ParamError("poly", "theta(1) = " + fmt_deg(t1) + " deg exceeds 180");
  if (std::abs(degrees(2 * t1) - fov) > 1e-2)
    throw ParamError("fov", fmt::format("with this poly the image circle spans 2 theta(1) = {} "
                                        "degrees; set fov to that (it is {:g})",
                                        fmt_deg(2 * t1), fov));
  return m;
}

// max_angle and min_elevation (see the table); a max_angle beyond the circle cuts nothing.
void read_cut_offs(const ParamValues& v, FisheyeGeometry* g) {
  if (v.has("max_angle")) g->cos_max_angle = std::cos(radians(v.number("max_angle")));
  if (v.has("min_elevation")) {
    g->sin_min_elevation = std::sin(radians(v.number("min_elevation")));
    g->up_cam = normalize(rig_from_look_at(v).inverse().vector({0, 1, 0}));
  }
}

VirtualCameraParts create_fisheye(const ParamValues& v, const ImageInfo& img) {
  check_params(kFisheyeParams, v);
  FisheyeGeometry g;
  g.map = read_mapping(v);
  const std::string& fit = v.string("fit");
  if (fit != "pixels" && v.has("circle_diameter"))
    throw ParamError("circle_diameter", "circle_diameter is only used with fit = \"pixels\"");
  double diameter;
  if (fit == "circle")
    diameter = std::min(img.width, img.height);
  else if (fit == "full_frame")
    diameter = std::hypot(double(img.width), double(img.height));
  else if (fit == "omnimax")
    diameter = std::min(double(img.width), kOmnimaxAspect * img.height);
  else if (v.has("circle_diameter"))
    diameter = v.number("circle_diameter");
  else
    throw ParamError("fit", "fit = \"pixels\" needs circle_diameter");
  set_circle(&g, img, diameter);
  if (fit == "omnimax") {
    if (v.has("circle_center"))
      throw ParamError("circle_center", "circle_center is set by fit = \"omnimax\"");
    if (img.width >= img.height) g.cv = diameter / (2.0 * img.height);
  } else if (v.has("circle_center")) {
    const Vec2 c = v.vec2("circle_center");
    g.cu = c.x, g.cv = c.y;
  }
  read_cut_offs(v, &g);
  return fisheye_parts(g, v,
                       fmt::format("fisheye {} {:g} deg (org point + dir fisheye sphere)",
                                   v.string("mapping"), v.number("fov")));
}

// --- mirror_ball -----------------------------------------------------------------------------

const ParamSpec kMirrorBallParams[] = {ANAMORPH_LOOK_AT_PARAMS};

VirtualCameraParts create_mirror_ball(const ParamValues& v, const ImageInfo& img) {
  check_params(kMirrorBallParams, v);
  // A distant camera looking along -z at a mirrored ball: the center reflects +z (back towards
  // that camera), the rim -z; right and up are the camera's (+x, +y). Normal tilt alpha = asin(r)
  // turns the ray by 2 alpha, so theta = 2 asin(r): equisolid over 360 degrees.
  FisheyeGeometry g;
  g.map.kind = FisheyeMapping::kEquisolid;
  g.map.theta_max = kPi;
  g.frame = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  set_circle(&g, img, std::min(img.width, img.height));
  return fisheye_parts(g, v, "mirror ball (org point + dir equisolid 360 sphere)");
}

// --- dome ------------------------------------------------------------------------------------

const ParamSpec kDomeParams[] = {
    {"look_from", ParamType::Vec3, "[0, 0, 0]", "Center of the dome (world)."},
    {"look_at", ParamType::Vec3, "[0, 0, -1]",
     "A point in the direction the audience faces (the front of the dome, world)."},
    {"up", ParamType::Vec3, "[0, 1, 0]", "The theatre's up (the zenith of an untilted dome)."},
    {.name = "fov",
     .type = ParamType::Number,
     .default_value = "180",
     .doc = "Angular diameter of the dome in degrees (180 = hemisphere).",
     .min = 0,
     .max = 360,
     .min_exclusive = true,
     .unit = "degrees"},
    {.name = "tilt",
     .type = ParamType::Number,
     .default_value = "0",
     .doc =
         "Dome tilt in degrees: the zenith leans towards the front (OMNIMAX and tilted planetaria "
         "use 10 to 30).",
     .min = -90,
     .max = 90,
     .unit = "degrees"},
    {.name = "radius",
     .type = ParamType::Number,
     .default_value = "1",
     .doc = "Dome radius in world units.",
     .min = 0,
     .min_exclusive = true,
     .unit = "scene units"},
    {.name = "eye_offset",
     .type = ParamType::Vec3,
     .default_value = "[0, 0, 0]",
     .doc = "The spectator's eye relative to the dome center, in world units in the theatre frame "
            "(x right, y up, z back); must lie inside the dome.",
     .unit = "scene units"},
};

// d dir / d key of a dome seen from its centre (the rays the unit directions of the frame): tilt
// turns the frame about x (axis = (0, cos t, -sin t)): d dir = -x cross dir per radian; fov scales
// the polar angle theta (equidistant: theta = r fov / 2) by theta / fov per degree.
PresetDerivatives::RayFn dome_ray_derivative(const Vec3& axis, double fov) {
  return [axis, fov](std::string_view key, const CameraRay& r, Vec3* dorg, Vec3* ddir) {
    *dorg = {};
    if (key == "tilt") {
      *ddir = cross(Vec3{1, 0, 0}, r.dir) * -(kPi / 180);
      return true;
    }
    if (key != "fov") return false;
    const double c = dot(r.dir, axis);
    const Vec3 perp = r.dir - axis * c;
    const double s = length(perp), theta = std::atan2(s, c);
    const double k = s > 1e-12 ? theta / s : 1;  // theta / sin(theta)
    *ddir = (perp * (k * c) - axis * (theta * s)) * (1 / fov);
    return true;
  };
}

VirtualCameraParts create_dome(const ParamValues& v, const ImageInfo& img) {
  check_params(kDomeParams, v);
  FisheyeGeometry g;
  g.map.kind = FisheyeMapping::kEquidistant;
  g.map.theta_max = radians(v.number("fov")) / 2;
  // Domemaster: image center = zenith, image bottom = the front of the dome, right = right.
  const double t = radians(v.number("tilt"));
  g.frame.axis = {0, std::cos(t), -std::sin(t)};
  g.frame.up = {0, std::sin(t), std::cos(t)};
  g.frame.right = {1, 0, 0};
  g.radius = v.number("radius");
  g.eye = v.vec3("eye_offset");
  if (!(length(g.eye) < g.radius))
    throw ParamError("eye_offset", "eye_offset must lie inside the dome (|eye_offset| < radius)");
  set_circle(&g, img, std::min(img.width, img.height));
  VirtualCameraParts p = fisheye_parts(g, v, "dome master (org point eye + dir dome sphere)");
  if (g.eye == Vec3{}) p.derivatives.ray = dome_ray_derivative(g.frame.axis, v.number("fov"));
  return p;
}

}  // namespace

const PresetInfo kFisheyePreset{
    "fisheye",
    "A fisheye lens: org = point, dir = a unit sphere laid out by the radial mapping theta(r) "
    "inside the image circle (no ray outside it).",
    kFisheyeParams, create_fisheye};

const PresetInfo kMirrorBallPreset{
    "mirror_ball",
    "A light probe: what a distant camera looking along look_at - look_from sees in a mirrored "
    "ball at look_from. Same functions as fisheye (equisolid, 360 degrees), seen in the mirror.",
    kMirrorBallParams, create_mirror_ball};

const PresetInfo kDomePreset{
    "dome",
    "Fulldome / OMNIMAX dome master: equidistant fisheye of the dome seen from its center; org = "
    "the spectator's eye, dir = dome point - eye (a sphere not concentric with the eye).",
    kDomeParams, create_dome};

}  // namespace anamorph
