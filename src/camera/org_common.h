// Helpers shared by the origin functions: reading ranges and frames from parameters, and turning
// derivatives in a surface's own parameters into a SurfaceSample.
#pragma once

#include <array>
#include <string_view>

#include "camera/functions.h"

namespace anamorph {

// A 3x3 matrix by columns: m * x = c0 x.x + c1 x.y + c2 x.z.
struct Mat3 {
  Vec3 c0{1, 0, 0}, c1{0, 1, 0}, c2{0, 0, 1};
  Vec3 operator*(const Vec3& x) const { return c0 * x.x + c1 * x.y + c2 * x.z; }
  double det() const { return dot(c0, cross(c1, c2)); }
  // The inverse transpose, which maps normals; requires det() != 0.
  Mat3 inverse_transpose() const {
    const double d = det();
    return {cross(c1, c2) / d, cross(c2, c0) / d, cross(c0, c1) / d};
  }
};

// A surface point with derivatives in the surface's own parameters (s, t) up to second order.
struct LocalGeom {
  Vec3 p, ps, pt, pss, pst, ptt;
};

// The local frame of a surface of revolution: canonical x -> right, y -> up (the axis),
// z -> back (so angle 0 lies at -z, "front", as for the default view).
struct AxisFrame {
  Vec3 right{1, 0, 0}, up{0, 1, 0}, back{0, 0, 1};
  Mat3 matrix() const { return {right, up, back}; }
};

// Reads `axis` (required non-zero) and the optional `front` (the direction of angle 0, projected
// perpendicular to the axis; default: -z projected, or +-y when the axis is along z).
AxisFrame read_axis_frame(const ParamValues& v, std::string_view axis_key = "axis",
                          std::string_view front_key = "front");

ParamRange read_range(const ParamValues& v, std::string_view key);
// A range given in degrees, returned in radians.
ParamRange read_angle_range(const ParamValues& v, std::string_view key);

// Fills p and its first and second image derivatives: own parameter s = s0 + su * u, t likewise.
void set_position(const LocalGeom& g, double su, double sv, SurfaceSample* out);

// Fills n, dndu, dndv from an unnormalized normal N and its derivatives in own parameters.
// Returns false (and zero normal fields) when N is zero.
bool set_normal(Vec3 N, Vec3 Ns, Vec3 Nt, double su, double sv, bool flip, SurfaceSample* out);

// The normal of an open parametric surface: N = ps x pt with its derivatives.
bool set_cross_normal(const LocalGeom& g, double su, double sv, bool flip, SurfaceSample* out);

// LocalGeom for up to kCameraBatch samples, structure of arrays.
struct LocalGeomBatch {
  static constexpr int N = kCameraBatch;
  double p[3][N], ps[3][N], pt[3][N], pss[3][N], pst[3][N], ptt[3][N];
  void set(int i, const LocalGeom& g) {
    SurfaceBatch::put(p, i, g.p), SurfaceBatch::put(ps, i, g.ps), SurfaceBatch::put(pt, i, g.pt);
    SurfaceBatch::put(pss, i, g.pss), SurfaceBatch::put(pst, i, g.pst);
    SurfaceBatch::put(ptt, i, g.ptt);
  }
  LocalGeom lane(int i) const {
    const auto at = [i](const double(&a)[3][N]) { return SurfaceBatch::at(a, i); };
    return {at(p), at(ps), at(pt), at(pss), at(pst), at(ptt)};
  }
};

// set_position and set_cross_normal for a batch, vectorized: lanes 0..n-1 of `out` (ok[i] true).
// Lanes whose derivatives are too short for a reliable cross product (|ps|^2 <= min_ps2,
// |pt|^2 <= min_pt2, ps nearly parallel to pt) or whose normal is not finite get check[i] = true
// and unspecified normal fields: the caller computes those one at a time. The others get the
// same bits as set_position and set_cross_normal.
void cross_normal_batch(const LocalGeomBatch& g, double su, double sv, bool flip, double min_ps2,
                        double min_pt2, int n, SurfaceBatch* out, bool* check);

// Maps a canonical sample through world = origin + m * canonical (normals map separately, by
// m.inverse_transpose(), which equals m for rotations).
LocalGeom transform_geom(const LocalGeom& g, const Mat3& m, Vec3 origin);

// The flip_normal parameter spec shared by every surface.
inline constexpr ParamSpec kFlipNormalParam{
    "flip_normal", ParamType::Bool, "false",
    "Reverse the normal (and its derivatives), e.g. so that dir = normal looks inward."};

// A parameter table made of a shared part and extra entries (tables are spans of ParamSpec).
template <size_t N, class... Extra>
constexpr std::array<ParamSpec, N + sizeof...(Extra)> join_params(const ParamSpec (&base)[N],
                                                                  const Extra&... extra) {
  std::array<ParamSpec, N + sizeof...(Extra)> out{};
  for (size_t i = 0; i < N; ++i) out[i] = base[i];
  size_t i = N;
  ((out[i++] = extra), ...);
  return out;
}

}  // namespace anamorph
