#include "camera/dir_scattered.h"

#include <cmath>

#include "camera/org_common.h"
#include "camera/scattered_common.h"

namespace anamorph {

namespace {

Vec3 unit_direction(const ScatteredDatum& d, size_t i) {
  const double l = length(d.value);
  if (!(l > 0) || !std::isfinite(l))
    throw ParamError("points", "points: point " + std::to_string(i) + " has no direction (" +
                                   "its [x, y, z] has length " + std::to_string(l) + ")");
  return d.value / l;
}

// dir(u, v) = S(u, v), the planar interpolant of the (normalized) data directions; the camera
// normalizes it.
class ScatteredDir final : public DirFunctionLoop<ScatteredDir> {
 public:
  explicit ScatteredDir(Rbf<2> rbf) : rbf_(std::move(rbf)) {}
  bool eval(Vec2 uv, const SurfaceSample&, DirSample* out) const override {
    Vec3 g[2];
    out->d = rbf_.eval({uv.x, uv.y}, g);
    out->dd_du = g[0], out->dd_dv = g[1];
    return true;
  }
  bool reads_org_beyond_first_order() const override { return false; }

 private:
  Rbf<2> rbf_;
};

const ParamSpec kPlanarParams[] = {
    {"points", ParamType::NumberGrid, "",
     "The data: one [u, v, x, y, z] per sample, the direction (x, y, z) (camera space; its length "
     "does not matter) of the ray at image position (u, v). Anywhere in the image (or up to 1e6 "
     "beyond it); no two at one (u, v)."},
    kRbfKernelParam,
    kRbfShapeParam,
    kRbfSmoothingParam,
};

std::unique_ptr<DirFunction> create_planar(const ParamValues& v) {
  check_params(kPlanarParams, v);
  return std::make_unique<ScatteredDir>(planar_rbf(v, unit_direction));
}

// Where image (u, v) lies on the unit sphere of directions before the pull, with derivatives;
// false outside the layout (a fisheye's corners). Camera space: -z ahead, +y up, +x right.
struct SphereLayout {
  bool fisheye = true;
  double half_angle = kPi / 2;  // fisheye: fov / 2
  ParamRange lon, lat;          // equirectangular, radians

  bool eval(Vec2 uv, Vec3* b, Vec3* bu, Vec3* bv) const {
    if (!fisheye) {
      const double lo = lon(uv.x), la = lat(uv.y);
      const double cl = std::cos(la), sl = std::sin(la), co = std::cos(lo), so = std::sin(lo);
      *b = {cl * so, sl, -cl * co};
      *bu = Vec3{cl * co, 0, cl * so} * lon.scale();
      *bv = Vec3{-sl * so, cl, sl * co} * lat.scale();
      return true;
    }
    // Equidistant: theta = k r around -z, b = (S(r) x, S(r) y, -cos theta), S = sin(theta) / r.
    const double x = 2 * uv.x - 1, y = 1 - 2 * uv.y, r2 = x * x + y * y, k = half_angle;
    if (r2 > 1) return false;
    const double r = std::sqrt(r2), t = k * r, st = std::sin(t), ct = std::cos(t);
    double S, T;  // T = S'(r) / r, by its series near the center where the quotient cancels
    if (r < 1e-4) {
      S = k - k * k * k * r2 / 6;
      T = -k * k * k / 3 + k * k * k * k * k * r2 / 30;
    } else {
      S = st / r;
      T = (t * ct - st) / (r2 * r);
    }
    *b = {S * x, S * y, -ct};
    const Vec3 bx{S + T * x * x, T * x * y, k * S * x}, by{T * x * y, S + T * y * y, k * S * y};
    *bu = bx * 2.0;
    *bv = by * -2.0;
    return true;
  }
};

// dir = F / |F| with F(u, v) = b(u, v) + R(b(u, v)): R interpolates the data's offsets from the
// layout over the sphere (chordal distance |b - b_i|), so with no pull nearby F is the layout
// and every datum's direction is met exactly. Unit directions with exact derivatives.
class ScatteredSphereDir final : public DirFunctionLoop<ScatteredSphereDir> {
 public:
  ScatteredSphereDir(SphereLayout l, Rbf<3> rbf) : layout_(l), rbf_(std::move(rbf)) {}
  bool eval(Vec2 uv, const SurfaceSample&, DirSample* out) const override {
    Vec3 b, bu, bv, g[3];
    if (!layout_.eval(uv, &b, &bu, &bv)) return false;
    const Vec3 F = b + rbf_.eval({b.x, b.y, b.z}, g);
    const Vec3 Fu = bu + g[0] * bu.x + g[1] * bu.y + g[2] * bu.z;
    const Vec3 Fv = bv + g[0] * bv.x + g[1] * bv.y + g[2] * bv.z;
    const double l = length(F);
    if (!(l > 1e-12)) return false;  // pulled onto the opposite of the layout: no direction
    const Vec3 d = F / l;
    *out = {d, (Fu - d * dot(d, Fu)) / l, (Fv - d * dot(d, Fv)) / l};
    return true;
  }
  bool unit_length() const override { return true; }
  bool reads_org_beyond_first_order() const override { return false; }

 private:
  SphereLayout layout_;
  Rbf<3> rbf_;
};

constexpr std::string_view kLayouts[] = {"fisheye", "equirectangular"};

const ParamSpec kSphereParams[] = {
    {"points", ParamType::NumberGrid, "",
     "The data: one [u, v, x, y, z] per sample, the direction (x, y, z) (camera space; its length "
     "does not matter) the ray at image position (u, v) must take instead of the layout's."},
    {"layout", ParamType::String, "\"fisheye\"",
     "The sphere of directions before the pull: fisheye (equidistant around -z, the circle "
     "inscribed in the image, as the dome preset on a square image; no ray outside it) or "
     "equirectangular (longitude u_range across, latitude v_range down).",
     -kInf, kInf, kLayouts},
    {.name = "fov",
     .type = ParamType::Number,
     .default_value = "180",
     .doc = "fisheye: the angular diameter of the image circle.",
     .min = 0,
     .max = 360,
     .min_exclusive = true,
     .unit = "degrees"},
    {.name = "u_range",
     .type = ParamType::Vec2,
     .default_value = "[-180, 180]",
     .doc = "equirectangular: longitude across the image, 0 = ahead (-z), 90 = right (+x).",
     .unit = "degrees"},
    {.name = "v_range",
     .type = ParamType::Vec2,
     .default_value = "[90, -90]",
     .doc = "equirectangular: latitude down the image, 90 = up (+y).",
     .unit = "degrees"},
    {"kernel", ParamType::String, "\"gaussian\"",
     "The radial basis phi of the chordal distance r = |b - b_i| (0 to 2) between layout "
     "directions: gaussian (exp(-(shape r)^2), the default: each sample pulls its neighbourhood "
     "and the rest stays as laid out), inverse_multiquadric, multiquadric (Pottmann & Eck), "
     "thin_plate or cubic (with a linear tail in x, y, z: a global warp).",
     -kInf, kInf, kRbfKernelNames},
    {"shape",
     ParamType::Number,
     "4",
     "The shape parameter (SciPy's epsilon): larger = smaller pulled regions (gaussian: a "
     "sample's pull falls to 1/e at chordal distance 1/shape, 4 = about 14 degrees).",
     0,
     kRbfShapeLimit,
     {},
     true},
    kRbfSmoothingParam,
};

std::unique_ptr<DirFunction> create_sphere(const ParamValues& v) {
  check_params(kSphereParams, v);
  SphereLayout layout;
  layout.fisheye = v.string("layout") == "fisheye";
  layout.half_angle = radians(v.number("fov")) / 2;
  layout.lon = read_angle_range(v, "u_range");
  layout.lat = read_angle_range(v, "v_range");
  std::vector<Rbf<3>::Point> at;
  std::vector<Vec3> offsets;
  const auto data = read_scattered_data(v, "points");
  for (size_t i = 0; i < data.size(); ++i) {
    Vec3 b, bu, bv;
    if (!layout.eval(data[i].uv, &b, &bu, &bv))
      throw ParamError("points", "points: point " + std::to_string(i) +
                                     " lies outside the fisheye's image circle");
    at.push_back({b.x, b.y, b.z});
    offsets.push_back(unit_direction(data[i], i) - b);
  }
  return rbf_param_errors("points", [&] {
    return std::make_unique<ScatteredSphereDir>(
        layout, Rbf<3>(std::move(at), offsets, read_rbf_kernel(v), v.number("shape"),
                       v.number("smoothing")));
  });
}

}  // namespace

const DirFunctionInfo kScatteredDirInfo{
    "scattered",
    "Directions through samples placed anywhere in the image: radial basis interpolation over "
    "(u, v) of [u, v, x, y, z] direction samples (each normalized first), the camera normalizing "
    "the result. Exact derivatives for ray differentials, coins and adaptive sampling.",
    kPlanarParams, create_planar};
const DirFunctionInfo kScatteredSphereDirInfo{
    "scattered_sphere",
    "A sphere of directions (a fisheye dome or an equirectangular panorama) pulled locally "
    "toward scattered direction samples: the offsets of [u, v, x, y, z] samples from the layout "
    "are interpolated over the sphere with chordal-distance radial basis functions (Pottmann & "
    "Eck's scattered data on the sphere) and the sum normalized. Meets every sample exactly "
    "(smoothing 0); exact tangential derivatives.",
    kSphereParams, create_sphere};

}  // namespace anamorph
