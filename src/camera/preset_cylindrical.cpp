// Longitude/latitude maps: equirectangular, cylindrical, mercator, lambert_equal_area.
// All are org = point and dir = LatLongDir, the unit sphere (equirectangular: the same directions
// as the generic sphere function with longitude and latitude ranges, in a form that vectorizes)
// or a cylinder or a Mercator map around the up axis, written as
//   dir(u,v) = (c sin(lon), s, -c cos(lon)),  lon = lon(u) linear,
// where (c, s) is (cos(lat), sin(lat)) up to a positive factor and comes from a vertical map
// coordinate y = y(v) that is linear in v. The maps differ only in y:
//   equirectangular y = lat; cylindrical (central) y = tan(lat); mercator y = ln tan(pi/4 +
//   lat/2); lambert_equal_area y = sin(lat).
// cylindrical with projection = "orthographic" instead moves the origin up the axis (org =
// segment, y = height) and keeps every ray horizontal.
#include <cmath>

#include "camera/dir_basic.h"
#include "camera/org_basic.h"
#include "camera/org_quadric.h"
#include "camera/preset_list.h"
#include "camera/preset_util.h"
#include "math/fast_trig.h"
#include "math/simd.h"

namespace anamorph {

namespace {

enum class LatMap { kLatitude, kTangent, kMercator, kSine, kHorizontal };

// Latitude (radians) to the map coordinate y, and back.
double lat_to_y(LatMap m, double lat) {
  switch (m) {
    case LatMap::kLatitude:
      return lat;
    case LatMap::kTangent:
      return std::tan(lat);
    case LatMap::kMercator:
      return std::asinh(std::tan(lat));
    case LatMap::kSine:
      return std::sin(lat);
    case LatMap::kHorizontal:
      return 0;
  }
  return 0;
}

struct LatLongGeometry {
  LatMap map = LatMap::kLatitude;
  AngleRange lon;
  double y_top = 0, y_bottom = 0;  // map coordinate at v = 0 and v = 1
};

// LatLongDir over a batch the compiler vectorizes: sincos_poly for the angles, exp_poly for
// mercator's sinh and cosh.
// The map is a template parameter: a branch on it inside the loop would keep it scalar.
template <LatMap M>
[[gnu::always_inline]] inline void latlong_kernel(const LatLongGeometry& geo,
                                                  const double* __restrict u,
                                                  const double* __restrict v, int n,
                                                  DirBatch* __restrict out) {
  const LatLongGeometry g = geo;  // a local copy: stores to `out` cannot alias it
  const double dlon = g.lon.span(), dy = g.y_bottom - g.y_top;
  const double fv = M == LatMap::kHorizontal ? 0.0 : dy;
  for (int i = 0; i < n; ++i) {
    const double lon = g.lon.lo + dlon * u[i];
    const double y = g.y_top + dy * v[i];
    double sl, cl, c = 1, s = 0, dc = 0, ds = 0;
    sincos_poly(lon, &sl, &cl);
    if constexpr (M == LatMap::kLatitude) {
      sincos_poly(y, &s, &c);
      dc = -s, ds = c;
    } else if constexpr (M == LatMap::kTangent) {
      s = y, ds = 1;
    } else if constexpr (M == LatMap::kSine) {
      const double yy = y < -1.0 ? -1.0 : (y > 1.0 ? 1.0 : y);
      c = std::sqrt(1 - yy * yy), s = yy, dc = -yy / (c > 1e-12 ? c : 1e-12), ds = 1;
    } else if constexpr (M == LatMap::kMercator) {  // (c, s) = (1, sinh y), ds = cosh y
      const double ep = exp_poly(y), em = exp_poly(-y);
      s = 0.5 * (ep - em), ds = 0.5 * (ep + em);
    }
    out->d[0][i] = c * sl, out->d[1][i] = s, out->d[2][i] = -c * cl;
    out->du[0][i] = c * cl * dlon, out->du[1][i] = 0, out->du[2][i] = c * sl * dlon;
    out->dv[0][i] = dc * sl * fv, out->dv[1][i] = ds * fv, out->dv[2][i] = -dc * cl * fv;
  }
  for (int i = 0; i < n; ++i) out->ok[i] = true;
}

template <LatMap M>
[[gnu::always_inline]] inline void latlong_run(const LatLongGeometry& g, const double* u,
                                               const double* v, int n, DirBatch* out) {
  with_trip_count<kCameraBatch>(
      n, [&](auto m) __attribute__((always_inline)) { latlong_kernel<M>(g, u, v, m, out); });
}

ANAMORPH_KERNEL_BODY void latlong_dirs_body(const LatLongGeometry& g, const double* u,
                                            const double* v, int n, DirBatch* out) {
  switch (g.map) {
    case LatMap::kLatitude:
      return latlong_run<LatMap::kLatitude>(g, u, v, n, out);
    case LatMap::kTangent:
      return latlong_run<LatMap::kTangent>(g, u, v, n, out);
    case LatMap::kSine:
      return latlong_run<LatMap::kSine>(g, u, v, n, out);
    case LatMap::kHorizontal:
      return latlong_run<LatMap::kHorizontal>(g, u, v, n, out);
    case LatMap::kMercator:
      return latlong_run<LatMap::kMercator>(g, u, v, n, out);
  }
}
constexpr simd::Kernel<latlong_dirs_body> latlong_dirs;

class LatLongDir final : public DirFunction {
 public:
  explicit LatLongDir(const LatLongGeometry& g) : g_(g) {}
  // One sample: a batch of one, so single rays and packets give the same bits.
  bool eval(Vec2 uv, const SurfaceSample& org, DirSample* out) const override {
    return eval_as_batch_of_one(*this, uv, org, out);
  }

  void eval_batch(const double* u, const double* v, int n, const SurfaceBatch&,
                  DirBatch* out) const override {
    latlong_dirs(g_, u, v, n, out);
  }
  // (cos(lat), sin(lat)) for the sphere and lambert, (1, 0) for the horizontal rays; the
  // cylinders' (1, y) are not.
  bool unit_length() const override {
    return g_.map == LatMap::kLatitude || g_.map == LatMap::kSine || g_.map == LatMap::kHorizontal;
  }

 private:
  LatLongGeometry g_;
};

// Closed form: longitude from atan2, the map coordinate from the point's elevation.
std::vector<Vec2> latlong_project(const LatLongGeometry& g, const Vec3& q) {
  const double rho = std::sqrt(q.x * q.x + q.z * q.z);
  double y = 0;
  switch (g.map) {
    case LatMap::kLatitude:
      y = std::atan2(q.y, rho);
      break;
    case LatMap::kTangent:
      if (!(rho > 0)) return {};
      y = q.y / rho;
      break;
    case LatMap::kMercator:
      if (!(rho > 0)) return {};
      y = std::asinh(q.y / rho);
      break;
    case LatMap::kSine: {
      const double len = length(q);
      if (!(len > 0)) return {};
      y = q.y / len;
      break;
    }
    case LatMap::kHorizontal:
      if (!(rho > 0)) return {};
      y = q.y;  // the origin's height on the axis
      break;
  }
  if (g.map != LatMap::kHorizontal && !(length(q) > 0)) return {};
  const double v = (y - g.y_top) / (g.y_bottom - g.y_top);
  if (!(v >= -1e-9 && v <= 1 + 1e-9)) return {};
  // At a pole every longitude is right; report the middle one.
  const double lon = rho > 0 ? std::atan2(q.x, -q.z) : 0.5 * (g.lon.lo + g.lon.hi);
  double us[3];
  const int n = longitude_to_u(lon, g.lon, us);
  std::vector<Vec2> out;
  for (int i = 0; i < n; ++i) out.push_back({us[i], std::clamp(v, 0.0, 1.0)});
  return out;
}

VirtualCameraParts latlong_parts(const LatLongGeometry& g, std::unique_ptr<OrgFunction> org,
                                 const ParamValues& v, std::string description,
                                 std::unique_ptr<DirFunction> dir = nullptr) {
  VirtualCameraParts p;
  p.org = std::move(org);
  p.dir = dir ? std::move(dir) : std::make_unique<LatLongDir>(g);
  p.world_from_camera = rig_from_look_at(v);
  p.description = std::move(description);
  p.inverse = make_inverse([g](const Vec3& q) { return latlong_project(g, q); });
  return p;
}

// Map-coordinate extent: from latitude_range when given, else square pixels on the equator
// (y spans lon_span * height / width, centered).
void set_vertical(LatLongGeometry* g, const ParamValues& v, const ImageInfo& img,
                  double limit_deg) {
  if (v.has("latitude_range")) {
    const AngleRange lat = read_angle_range(v, "latitude_range", 90);
    if (limit_deg < 90 && (lat.lo <= -radians(limit_deg) || lat.hi >= radians(limit_deg)))
      throw ParamError("latitude_range", "latitude_range must lie strictly inside (-90, 90) here");
    g->y_top = lat_to_y(g->map, lat.hi);
    g->y_bottom = lat_to_y(g->map, lat.lo);
  } else {
    const double half = 0.5 * g->lon.span() / img.aspect();
    g->y_top = half;
    g->y_bottom = -half;
  }
}

#define ANAMORPH_LONGITUDE_PARAM                                                             \
  {                                                                                          \
    "longitude_range", ParamType::Vec2, "[-180, 180]",                                       \
        "Longitudes in degrees at the left and right image edges (0 = look_at, positive to " \
        "the right); at most 360 apart.",                                                    \
        -720, 720                                                                            \
  }

// --- equirectangular -------------------------------------------------------------------------

const ParamSpec kEquirectParams[] = {
    ANAMORPH_LOOK_AT_PARAMS,
    ANAMORPH_LONGITUDE_PARAM,
    {.name = "latitude_range",
     .type = ParamType::Vec2,
     .default_value = "[-90, 90]",
     .doc = "Latitudes in degrees at the bottom and top image edges (0 = the horizon).",
     .min = -90,
     .max = 90,
     .unit = "degrees"},
};

VirtualCameraParts create_equirect(const ParamValues& v, const ImageInfo& img) {
  check_params(kEquirectParams, v);
  LatLongGeometry g;
  g.map = LatMap::kLatitude;
  g.lon = read_angle_range(v, "longitude_range", 180);
  set_vertical(&g, v, img, 90);
  return latlong_parts(g, make_point_org({}), v, "equirectangular (org point + dir sphere)");
}

// --- cylindrical -----------------------------------------------------------------------------

const std::string_view kCylProjections[] = {"central", "orthographic"};

const ParamSpec kCylParams[] = {
    ANAMORPH_LOOK_AT_PARAMS,
    ANAMORPH_LONGITUDE_PARAM,
    {"projection", ParamType::String, "\"central\"",
     "\"central\": every ray from look_from through a cylinder around the up axis (y = tan(lat)); "
     "\"orthographic\": horizontal rays from origins moving up the axis (y = height).",
     -kInf, kInf, kCylProjections},
    {.name = "latitude_range",
     .type = ParamType::Vec2,
     .default_value = "none",
     .doc = "central: latitudes in degrees at the bottom and top edges, inside (-90, 90). Default: "
            "square pixels on the horizon.",
     .min = -90,
     .max = 90,
     .unit = "degrees"},
    {.name = "height",
     .type = ParamType::Number,
     .default_value = "none",
     .doc =
         "orthographic: height of the axis segment in world units, centered on look_from. Default: "
         "square pixels at distance 1.",
     .min = 0,
     .min_exclusive = true,
     .unit = "scene units"},
};

VirtualCameraParts create_cylindrical(const ParamValues& v, const ImageInfo& img) {
  check_params(kCylParams, v);
  LatLongGeometry g;
  g.lon = read_angle_range(v, "longitude_range", 180);
  if (v.string("projection") == "central") {
    if (v.has("height")) throw ParamError("height", "height is for projection = \"orthographic\"");
    g.map = LatMap::kTangent;
    set_vertical(&g, v, img, 89.999999);
    return latlong_parts(g, make_point_org({}), v,
                         "cylindrical central (org point + dir cylinder)");
  }
  if (v.has("latitude_range"))
    throw ParamError("latitude_range", "latitude_range is for projection = \"central\"");
  g.map = LatMap::kHorizontal;
  const double h = v.has("height") ? v.number("height") : g.lon.span() / img.aspect();
  g.y_top = h / 2;
  g.y_bottom = -h / 2;
  return latlong_parts(g, make_segment_org({}, {0, -h, 0}, true), v,
                       "cylindrical orthographic (org axis segment + dir horizontal)");
}

// --- mercator --------------------------------------------------------------------------------

const ParamSpec kMercatorParams[] = {
    ANAMORPH_LOOK_AT_PARAMS,
    ANAMORPH_LONGITUDE_PARAM,
    {.name = "latitude_range",
     .type = ParamType::Vec2,
     .default_value = "none",
     .doc = "Latitudes in degrees at the bottom and top edges, inside (-90, 90). Default: square "
            "pixels (the map is conformal), centered on the horizon.",
     .min = -90,
     .max = 90,
     .unit = "degrees"},
};

VirtualCameraParts create_mercator(const ParamValues& v, const ImageInfo& img) {
  check_params(kMercatorParams, v);
  LatLongGeometry g;
  g.map = LatMap::kMercator;
  g.lon = read_angle_range(v, "longitude_range", 180);
  set_vertical(&g, v, img, 89.999999);
  return latlong_parts(g, make_point_org({}), v, "mercator (org point + dir cylinder, y = ln tan)");
}

// --- lambert_equal_area ----------------------------------------------------------------------

const ParamSpec kLambertParams[] = {
    ANAMORPH_LOOK_AT_PARAMS,
    ANAMORPH_LONGITUDE_PARAM,
    {.name = "latitude_range",
     .type = ParamType::Vec2,
     .default_value = "[-90, 90]",
     .doc = "Latitudes in degrees at the bottom and top image edges.",
     .min = -90,
     .max = 90,
     .unit = "degrees"},
};

VirtualCameraParts create_lambert(const ParamValues& v, const ImageInfo& img) {
  check_params(kLambertParams, v);
  LatLongGeometry g;
  g.map = LatMap::kSine;
  g.lon = read_angle_range(v, "longitude_range", 180);
  set_vertical(&g, v, img, 90);
  return latlong_parts(g, make_point_org({}), v,
                       "lambert cylindrical equal-area (org point + dir cylinder, y = sin lat)");
}

}  // namespace

const PresetInfo kEquirectangularPreset{
    "equirectangular",
    "Longitude and latitude linear in u and v: org = point, dir = the unit sphere (the paper's "
    "sphere function used for dir).",
    kEquirectParams, create_equirect};

const PresetInfo kCylindricalPreset{
    "cylindrical",
    "Panorama on a cylinder around the up axis: central (org point, dir through the cylinder) "
    "or orthographic along the axis (org axis segment, horizontal dir).",
    kCylParams, create_cylindrical};

const PresetInfo kMercatorPreset{
    "mercator",
    "Mercator's conformal cylindrical map: y = ln tan(pi/4 + lat/2). org = point, dir = "
    "cylinder with that height.",
    kMercatorParams, create_mercator};

const PresetInfo kLambertEqualAreaPreset{
    "lambert_equal_area",
    "Lambert's cylindrical equal-area map: y = sin(lat), every pixel covers the same solid "
    "angle. org = point, dir = cylinder with that height.",
    kLambertParams, create_lambert};

}  // namespace anamorph
