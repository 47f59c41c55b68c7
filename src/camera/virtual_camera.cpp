#include "camera/virtual_camera.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "math/frame.h"
#include "math/input_limits.h"
#include "math/sampling.h"
#include "math/simd.h"

namespace anamorph {

VirtualCamera::VirtualCamera(VirtualCameraParts parts, DepthOfField dof)
    : org_(std::move(parts.org)),
      dir_(std::move(parts.dir)),
      inverse_(std::move(parts.inverse)),
      world_from_camera_(parts.world_from_camera),
      rig_identity_(parts.world_from_camera.is_identity()),
      rig_affine_(parts.world_from_camera.matrix().m[3] == std::array<double, 4>{0, 0, 0, 1}),
      dof_(dof),
      description_(std::move(parts.description)) {
  shutter_ = parts.shutter;
  if (parts.world_from_camera_close) {
    moving_ = !(parts.world_from_camera_close->matrix() == world_from_camera_.matrix());
    if (moving_) motion_ = RigidMotion(world_from_camera_, *parts.world_from_camera_close);
  }
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) {
      rig34_.m[r][c] = world_from_camera_.matrix().m[size_t(r)][size_t(c)];
      camera34_.m[r][c] = r == c ? 1.0 : 0.0;
    }
  // Rigs built from look_at are orthonormal to a few units in the last place; a scale makes
  // the finish normalize again.
  double worst = 0;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      double dot_ab = 0;
      for (int r = 0; r < 3; ++r) dot_ab += rig34_.m[r][a] * rig34_.m[r][b];
      worst = std::max(worst, std::abs(dot_ab - (a == b ? 1.0 : 0.0)));
    }
  rig_rotation_ = rig_affine_ && worst < 1e-15;
  unit_dirs_ = dir_->unit_length();
  org_first_order_ = !dir_->reads_org_beyond_first_order();
  detect_linear_field();
  detect_point_origin();
  if (!parts.coins.empty()) {
    // (uc, vc) come from the undistorted camera: coins_ is still empty while projecting.
    coins_ = CoinField(
        parts.coins, world_from_camera_.inverse(), [this](const Vec3& p) { return project(p); },
        *org_, &coin_warnings_);
    if (!coins_.empty())
      description_ += " + " + std::to_string(parts.coins.size()) +
                      (parts.coins.size() == 1 ? " coin" : " coins");
  }
}

void VirtualCamera::detect_linear_field() {
  // Probe the functions on a grid plus a few irrational positions; an affine org and dir must
  // reproduce every probe from the corner values and derivatives. Functions that are only
  // piecewise affine (quilts, cubemaps) or curved fail the test and keep the general path.
  SurfaceSample s0;
  DirSample d0;
  if (!org_->eval({0, 0}, &s0) || !dir_->eval({0, 0}, s0, &d0)) return;
  std::vector<Vec2> probes;
  for (int j = 0; j <= 4; ++j)
    for (int i = 0; i <= 4; ++i) probes.push_back({i / 4.0, j / 4.0});
  probes.push_back({0.3819660112501051, 0.6180339887498949});
  probes.push_back({0.7071067811865476, 0.1415926535897932});
  probes.push_back({0.0577215664901533, 0.9189385332046727});
  const double scale_o = 1 + length(s0.p) + length(s0.dpdu) + length(s0.dpdv);
  const double scale_d = length(d0.d) + length(d0.dd_du) + length(d0.dd_dv);
  if (!(scale_d > 0)) return;
  for (const Vec2& uv : probes) {
    SurfaceSample s;
    DirSample d;
    if (!org_->eval(uv, &s) || !dir_->eval(uv, s, &d)) return;
    const Vec3 po = s0.p + s0.dpdu * uv.x + s0.dpdv * uv.y;
    const Vec3 pd = d0.d + d0.dd_du * uv.x + d0.dd_dv * uv.y;
    if (length(s.p - po) > 1e-12 * scale_o || length(s.dpdu - s0.dpdu) > 1e-12 * scale_o ||
        length(s.dpdv - s0.dpdv) > 1e-12 * scale_o)
      return;
    if (length(d.d - pd) > 1e-12 * scale_d || length(d.dd_du - d0.dd_du) > 1e-12 * scale_d ||
        length(d.dd_dv - d0.dd_dv) > 1e-12 * scale_d || !(length(d.d) > 0))
      return;
  }
  co0_ = s0.p;
  co_u_ = s0.dpdu;
  co_v_ = s0.dpdv;
  cd0_ = d0.d;
  cd_u_ = d0.dd_du;
  cd_v_ = d0.dd_dv;
  const Transform& t = world_from_camera_;
  o0_ = t.point(s0.p);
  o_u_ = t.vector(s0.dpdu);
  o_v_ = t.vector(s0.dpdv);
  d0_ = t.vector(d0.d);
  d_u_ = t.vector(d0.dd_du);
  d_v_ = t.vector(d0.dd_dv);
  linear_ = true;
}

void VirtualCamera::detect_point_origin() {
  // A single point answers every probe with the same bits and no derivatives.
  SurfaceSample s0;
  if (!org_->eval({0.5, 0.5}, &s0) || !is_finite(s0.p)) return;
  const Vec3 zero{};
  for (double u : {0.0, 0.25, 0.3819660112501051, 1.0})
    for (double v : {0.0, 0.7071067811865476, 1.0}) {
      SurfaceSample s;
      if (!org_->eval({u, v}, &s) || !(s.p == s0.p) || !(s.dpdu == zero) || !(s.dpdv == zero) ||
          !(s.n == s0.n) || !(s.dndu == zero) || !(s.dndv == zero) || !(s.dpduu == s0.dpduu) ||
          !(s.dpduv == s0.dpduv) || !(s.dpdvv == s0.dpdvv))
        return;
    }
  point_org_ = true;
  point_batch_ = std::make_unique<SurfaceBatch>();
  for (int i = 0; i < kCameraBatch; ++i) point_batch_->set(i, s0), point_batch_->ok[i] = true;
}

// Unit direction and its derivative: d(d/|d|) = (dd - n (n . dd)) / |d|.
static Vec3 normalized_derivative(const Vec3& n, double len, const Vec3& dd) {
  return (dd - n * dot(n, dd)) / len;
}

// An affine field's ray in camera space from its closed form, deformed by the coins.
std::optional<CameraRay> VirtualCamera::linear_coin_ray(Vec2 uv) const {
  const Vec3 d = cd0_ + cd_u_ * uv.x + cd_v_ * uv.y;
  const double len = length(d);
  if (!(len > 0) || !std::isfinite(len)) return std::nullopt;
  CameraRay r;
  r.org = co0_ + co_u_ * uv.x + co_v_ * uv.y;
  r.dir = d / len;
  r.dorg_du = co_u_;
  r.dorg_dv = co_v_;
  r.ddir_du = normalized_derivative(r.dir, len, cd_u_);
  r.ddir_dv = normalized_derivative(r.dir, len, cd_v_);
  if (!coins_.apply(uv, &r)) return std::nullopt;
  return r;
}

std::optional<CameraRay> VirtualCamera::generate_pinhole(Vec2 uv) const {
  // An affine field under a coin: its closed form instead of the function calls (samples no coin
  // reaches keep the exact path they have without coins).
  if (linear_ && coins_.reaches(uv)) return linear_coin_ray(uv);
  SurfaceSample s;
  if (!org_->eval(uv, &s)) return std::nullopt;
  DirSample d;
  if (!dir_->eval(uv, s, &d)) return std::nullopt;
  const double len = length(d.d);
  // A zero-length or non-finite direction means "no ray", never NaN.
  if (!(len > 0) || !std::isfinite(len) || !is_finite(s.p)) return std::nullopt;
  CameraRay r;
  r.org = s.p;
  r.dir = d.d / len;
  r.dorg_du = s.dpdu;
  r.dorg_dv = s.dpdv;
  r.ddir_du = normalized_derivative(r.dir, len, d.dd_du);
  r.ddir_dv = normalized_derivative(r.dir, len, d.dd_dv);
  // Coins deform the ray field org/dir define (the paper: independent of the functions).
  if (!coins_.apply(uv, &r)) return std::nullopt;
  return r;
}

double VirtualCamera::shutter_time(const CameraSample& cs) const {
  if (!shutter_.rolling) return cs.time;
  const double a = radians(shutter_.rolling_angle), c = std::cos(a), s = std::sin(a);
  return std::clamp(0.5 + ((cs.uv.x - 0.5) * c + (cs.uv.y - 0.5) * s) / (std::abs(c) + std::abs(s)),
                    0.0, 1.0);
}

std::optional<CameraRay> VirtualCamera::generate(const CameraSample& cs) const {
  std::optional<CameraRay> r = generate_any(cs);
  if (r && !within_world(r->org)) return std::nullopt;
  return r;
}

void VirtualCamera::generate_batch(const CameraSample* s, int n, CameraRayBatch* out) const {
  generate_batch_any(s, n, out);
  // (The same test as generate()'s, on the same values: single rays and packets agree.)
  for (int i = 0; i < n; ++i)
    out->valid[i] = out->valid[i] && within_world(CameraRayBatch::at(out->org, i));
}

std::optional<CameraRay> VirtualCamera::generate_any(const CameraSample& cs) const {
  if (moving_) {
    // Motion blur: the ray in camera space, then the rig where it is at this sample's time.
    auto r = generate_general(cs, /*camera_space=*/true);
    if (r) to_world(&*r, motion_.at(shutter_time(cs)));
    return r;
  }
  if (linear_ && dof_.aperture_radius == 0) {
    if (coins_.reaches(cs.uv)) {
      // The packet path with one sample, so that single rays and packets agree.
      CameraRayBatch b;
      linear_coin_rays(&cs.uv.x, &cs.uv.y, 1, &b);
      if (!b.valid[0]) return std::nullopt;
      return b.ray(0);
    }
    const double u = cs.uv.x, v = cs.uv.y;
    const Vec3 d = d0_ + d_u_ * u + d_v_ * v;
    const double len = length(d);
    if (!(len > 0) || !std::isfinite(len)) return std::nullopt;
    const double inv = 1 / len;  // one division for the direction and both derivatives
    CameraRay r;
    r.org = o0_ + o_u_ * u + o_v_ * v;
    r.dir = d * inv;
    r.dorg_du = o_u_;
    r.dorg_dv = o_v_;
    r.ddir_du = (d_u_ - r.dir * dot(r.dir, d_u_)) * inv;
    r.ddir_dv = (d_v_ - r.dir * dot(r.dir, d_v_)) * inv;
    return r;
  }
  if (dof_.aperture_radius == 0 && rig_affine_) {
    CameraRayBatch b;
    if (coins_.empty())
      plain_rays(&cs.uv.x, &cs.uv.y, 1, &b);
    else
      coin_rays(&cs.uv.x, &cs.uv.y, 1, &b);
    if (!b.valid[0]) return std::nullopt;
    return b.ray(0);
  }
  return generate_general(cs);
}

namespace {

// The affine ray field for a batch, in structure-of-arrays form so the compiler vectorizes it;
// compiled for several ISAs, chosen at load time (math/simd.h).
struct LinearField {
  Vec3 o0, o_u, o_v, d0, d_u, d_v;
};

// The loops below write straight into the batch's arrays. Masks are formed in loops of their
// own: bool stores from double lanes keep GCC from vectorizing a loop. Each kernel is inlined
// with n = 16 (full packets: full vectors, no remainder loop) and n = 1 (generate(): straight-line
// code) as constants.
[[gnu::always_inline]] inline void linear_kernel(const LinearField& f, const double* __restrict u,
                                                 const double* __restrict v, int n,
                                                 CameraRayBatch* __restrict out) {
  const LinearField g = f;  // a local copy: stores to `out` cannot alias it
  constexpr int N = kCameraBatch;
  alignas(64) double invs[N];
  for (int i = 0; i < n; ++i) {
    const double dx = g.d0.x + g.d_u.x * u[i] + g.d_v.x * v[i];
    const double dy = g.d0.y + g.d_u.y * u[i] + g.d_v.y * v[i];
    const double dz = g.d0.z + g.d_u.z * u[i] + g.d_v.z * v[i];
    const double inv = 1 / std::sqrt(dx * dx + dy * dy + dz * dz);
    invs[i] = inv;
    out->org[0][i] = g.o0.x + g.o_u.x * u[i] + g.o_v.x * v[i];
    out->org[1][i] = g.o0.y + g.o_u.y * u[i] + g.o_v.y * v[i];
    out->org[2][i] = g.o0.z + g.o_u.z * u[i] + g.o_v.z * v[i];
    const double nx = dx * inv, ny = dy * inv, nz = dz * inv;
    out->dir[0][i] = nx, out->dir[1][i] = ny, out->dir[2][i] = nz;
    out->dorg_du[0][i] = g.o_u.x, out->dorg_du[1][i] = g.o_u.y, out->dorg_du[2][i] = g.o_u.z;
    out->dorg_dv[0][i] = g.o_v.x, out->dorg_dv[1][i] = g.o_v.y, out->dorg_dv[2][i] = g.o_v.z;
    // d(d/|d|) = (dd - n (n . dd)) / |d|
    const double pu = nx * g.d_u.x + ny * g.d_u.y + nz * g.d_u.z;
    const double pv = nx * g.d_v.x + ny * g.d_v.y + nz * g.d_v.z;
    out->ddir_du[0][i] = (g.d_u.x - nx * pu) * inv, out->ddir_du[1][i] = (g.d_u.y - ny * pu) * inv,
    out->ddir_du[2][i] = (g.d_u.z - nz * pu) * inv;
    out->ddir_dv[0][i] = (g.d_v.x - nx * pv) * inv, out->ddir_dv[1][i] = (g.d_v.y - ny * pv) * inv,
    out->ddir_dv[2][i] = (g.d_v.z - nz * pv) * inv;
  }
  for (int i = 0; i < n; ++i) out->valid[i] = (invs[i] * 0 == 0) & (invs[i] > 0);
}

ANAMORPH_SIMD_CLONES void linear_rays(const LinearField& f, const double* u, const double* v, int n,
                                      CameraRayBatch* out) {
  with_trip_count<kCameraBatch>(
      n, [&](auto m) __attribute__((always_inline)) { linear_kernel(f, u, v, m, out); });
}

// The rig, normalization and ray differentials for a batch of directions from org/dir. Every
// ray goes through here, batched or not, so the bits agree.
using Rig = AffineRig;

// kIdentity: the rig is the identity (camera space, or functions given in world space), whose
// products would only add zeros. kUnit: the directions are unit vectors with perpendicular
// derivatives (DirFunction::unit_length) and the rig keeps lengths, so normalizing would only
// round them again.
template <bool kPointOrg, bool kIdentity, bool kUnit>
[[gnu::always_inline]] inline void finish_rays(const Rig& t, const SurfaceBatch& __restrict org,
                                               const DirBatch& __restrict b, int n,
                                               CameraRayBatch* __restrict out) {
  const Rig rig = t;  // a local copy: stores to `out` cannot alias it
  const auto& m = rig.m;
  const auto vec = [&](const Vec3& a) __attribute__((always_inline)) {
    if (kIdentity) return a;
    return Vec3{m[0][0] * a.x + m[0][1] * a.y + m[0][2] * a.z,
                m[1][0] * a.x + m[1][1] * a.y + m[1][2] * a.z,
                m[2][0] * a.x + m[2][1] * a.y + m[2][2] * a.z};
  };

  constexpr int N = kCameraBatch;
  alignas(64) double lens[N], finite[N];
  if (!kPointOrg)
    for (int i = 0; i < n; ++i) {
      const Vec3 du = vec(SurfaceBatch::at(org.dpdu, i)), dv = vec(SurfaceBatch::at(org.dpdv, i));
      out->dorg_du[0][i] = du.x, out->dorg_du[1][i] = du.y, out->dorg_du[2][i] = du.z;
      out->dorg_dv[0][i] = dv.x, out->dorg_dv[1][i] = dv.y, out->dorg_dv[2][i] = dv.z;
    }
  const Vec3 p0 = SurfaceBatch::at(org.p, 0);
  const Vec3 point_du = kPointOrg ? vec(SurfaceBatch::at(org.dpdu, 0)) : Vec3{},
             point_dv = kPointOrg ? vec(SurfaceBatch::at(org.dpdv, 0)) : Vec3{};
  for (int i = 0; i < n; ++i) {
    const double px = kPointOrg ? p0.x : org.p[0][i], py = kPointOrg ? p0.y : org.p[1][i],
                 pz = kPointOrg ? p0.z : org.p[2][i];
    const bool I = kIdentity;
    const double ox = I ? px : m[0][0] * px + m[0][1] * py + m[0][2] * pz + m[0][3];
    const double oy = I ? py : m[1][0] * px + m[1][1] * py + m[1][2] * pz + m[1][3];
    const double oz = I ? pz : m[2][0] * px + m[2][1] * py + m[2][2] * pz + m[2][3];
    const double* d[3] = {b.d[0], b.d[1], b.d[2]};
    const double *du[3] = {b.du[0], b.du[1], b.du[2]}, *dv[3] = {b.dv[0], b.dv[1], b.dv[2]};
    const auto row = [&](int r, const double* const* a) __attribute__((always_inline)) {
      return I ? a[r][i] : m[r][0] * a[0][i] + m[r][1] * a[1][i] + m[r][2] * a[2][i];
    };
    const double dx = row(0, d), dy = row(1, d), dz = row(2, d);
    const double ux = row(0, du), uy = row(1, du), uz = row(2, du);
    const double vx = row(0, dv), vy = row(1, dv), vz = row(2, dv);
    out->org[0][i] = ox, out->org[1][i] = oy, out->org[2][i] = oz;
    if (kPointOrg) {
      out->dorg_du[0][i] = point_du.x, out->dorg_du[1][i] = point_du.y;
      out->dorg_du[2][i] = point_du.z;
      out->dorg_dv[0][i] = point_dv.x, out->dorg_dv[1][i] = point_dv.y;
      out->dorg_dv[2][i] = point_dv.z;
    }
    // A zero-length or non-finite direction, or a non-finite origin, means no ray (never NaN);
    // x * 0 == 0 holds exactly for finite x.
    if (kUnit) {
      lens[i] = dx * dx + dy * dy + dz * dz;  // 1, or 0 for a function's zero vector
      finite[i] = (dx + dy + dz) * 0 + (ox + oy + oz) * 0;
      out->dir[0][i] = dx, out->dir[1][i] = dy, out->dir[2][i] = dz;
      out->ddir_du[0][i] = ux, out->ddir_du[1][i] = uy, out->ddir_du[2][i] = uz;
      out->ddir_dv[0][i] = vx, out->ddir_dv[1][i] = vy, out->ddir_dv[2][i] = vz;
      continue;
    }
    const double len = std::sqrt(dx * dx + dy * dy + dz * dz);
    const double inv = 1 / len;
    lens[i] = len;
    finite[i] = len * 0 + (ox + oy + oz) * 0;
    const double nx = dx * inv, ny = dy * inv, nz = dz * inv;
    out->dir[0][i] = nx, out->dir[1][i] = ny, out->dir[2][i] = nz;
    // d(d/|d|) = (dd - n (n . dd)) / |d|
    const double pu = nx * ux + ny * uy + nz * uz, pv = nx * vx + ny * vy + nz * vz;
    out->ddir_du[0][i] = (ux - nx * pu) * inv, out->ddir_du[1][i] = (uy - ny * pu) * inv,
    out->ddir_du[2][i] = (uz - nz * pu) * inv;
    out->ddir_dv[0][i] = (vx - nx * pv) * inv, out->ddir_dv[1][i] = (vy - ny * pv) * inv,
    out->ddir_dv[2][i] = (vz - nz * pv) * inv;
  }
  // Two loops: comparisons of doubles and ANDs of bools each vectorize, mixed they stay scalar.
  for (int i = 0; i < n; ++i) out->valid[i] = (lens[i] > 0) & (finite[i] == 0);
  for (int i = 0; i < n; ++i) out->valid[i] = out->valid[i] & b.ok[i] & (kPointOrg || org.ok[i]);
}

// How finish_rays is instantiated for a camera: with or without a rig to apply, with or without
// normalization.
struct FinishMode {
  bool identity, unit;
};

template <bool kPointOrg>
[[gnu::always_inline]] inline void finish_rays_any_rig(const Rig& t, FinishMode mode,
                                                       const SurfaceBatch& org, const DirBatch& b,
                                                       int n, CameraRayBatch* out) {
  with_trip_count<kCameraBatch>(
      n, [&](auto m) __attribute__((always_inline)) {
        if (mode.identity) {
          if (mode.unit)
            finish_rays<kPointOrg, true, true>(t, org, b, m, out);
          else
            finish_rays<kPointOrg, true, false>(t, org, b, m, out);
        } else {
          if (mode.unit)
            finish_rays<kPointOrg, false, true>(t, org, b, m, out);
          else
            finish_rays<kPointOrg, false, false>(t, org, b, m, out);
        }
      });
}

ANAMORPH_SIMD_CLONES void finish_point_org(const Rig& t, FinishMode mode, const SurfaceBatch& org,
                                           const DirBatch& b, int n, CameraRayBatch* out) {
  finish_rays_any_rig<true>(t, mode, org, b, n, out);
}

ANAMORPH_SIMD_CLONES void finish_any_org(const Rig& t, FinishMode mode, const SurfaceBatch& org,
                                         const DirBatch& b, int n, CameraRayBatch* out) {
  finish_rays_any_rig<false>(t, mode, org, b, n, out);
}

}  // namespace

const SurfaceBatch& VirtualCamera::eval_functions(const double* u, const double* v, int n,
                                                  SurfaceBatch* org, DirBatch* dir) const {
  if (point_org_) {
    dir_->eval_batch(u, v, n, *point_batch_, dir);
    return *point_batch_;
  }
  if (org_first_order_)
    org_->eval_batch_first_order(u, v, n, org);
  else
    org_->eval_batch(u, v, n, org);
  dir_->eval_batch(u, v, n, *org, dir);
  return *org;
}

void VirtualCamera::finish(const SurfaceBatch& org, const DirBatch& dir, bool camera_space, int n,
                           CameraRayBatch* out) const {
  const Rig& rig = camera_space ? camera34_ : rig34_;
  // (The identity is a rotation too.)
  const FinishMode mode{camera_space || rig_identity_,
                        unit_dirs_ && (camera_space || rig_rotation_)};
  if (point_org_)
    finish_point_org(rig, mode, org, dir, n, out);
  else
    finish_any_org(rig, mode, org, dir, n, out);
}

void VirtualCamera::plain_rays(const double* u, const double* v, int n, CameraRayBatch* out,
                               bool camera_space) const {
  SurfaceBatch org;
  DirBatch dir;
  finish(eval_functions(u, v, n, &org, &dir), dir, camera_space, n, out);
}

void VirtualCamera::generate_batch_any(const CameraSample* s, int n, CameraRayBatch* out) const {
  if (moving_ || dof_.aperture_radius > 0 || !rig_affine_) {
    for (int i = 0; i < n; ++i) out->set(i, generate_any(s[i]));
    return;
  }
  alignas(64) double u[kCameraBatch], v[kCameraBatch];
  split_sample_positions(s, n, u, v);
  if (!linear_) {
    if (coins_.empty())
      plain_rays(u, v, n, out);
    else
      coin_rays(u, v, n, out);
    return;
  }
  if (coins_.empty())
    linear_rays(LinearField{o0_, o_u_, o_v_, d0_, d_u_, d_v_}, u, v, n, out);
  else
    linear_coin_rays(u, v, n, out);
}

void VirtualCamera::linear_coin_rays(const double* u, const double* v, int n,
                                     CameraRayBatch* out) const {
  linear_rays(LinearField{o0_, o_u_, o_v_, d0_, d_u_, d_v_}, u, v, n, out);
  if (!coins_.may_reach(u, v, n)) return;
  CameraRayBatch plain;
  linear_rays(LinearField{co0_, co_u_, co_v_, cd0_, cd_u_, cd_v_}, u, v, n, &plain);
  deform_by_coins(u, v, n, &plain, out);
}

void VirtualCamera::coin_rays(const double* u, const double* v, int n, CameraRayBatch* out) const {
  // The functions once for all samples; samples no coin reaches finish as without coins (same
  // bits), the others in camera space, deformed, then through the rig.
  SurfaceBatch org_storage;
  DirBatch dir;
  const SurfaceBatch& org = eval_functions(u, v, n, &org_storage, &dir);
  finish(org, dir, /*camera_space=*/false, n, out);
  if (!coins_.may_reach(u, v, n)) return;
  CameraRayBatch plain;
  if (rig_identity_)
    plain = *out;  // the same finishing pass (the identity's products are skipped either way)
  else
    finish(org, dir, /*camera_space=*/true, n, &plain);
  deform_by_coins(u, v, n, &plain, out);
}

void VirtualCamera::deform_by_coins(const double* u, const double* v, int n, CameraRayBatch* plain,
                                    CameraRayBatch* out) const {
  bool reached[kCameraBatch];
  coins_.apply_batch(u, v, n, plain, reached);
  for (int k = 0; k < n; ++k) {
    if (!reached[k]) continue;
    CameraRay r = plain->ray(k);
    if (plain->valid[k]) to_world(&r);
    out->set(k, plain->valid[k] ? std::optional(r) : std::nullopt);
  }
}

std::optional<CameraRay> VirtualCamera::generate_general(const CameraSample& cs,
                                                         bool camera_space) const {
  auto r = generate_pinhole(cs.uv);
  if (!r) return r;
  if (dof_.aperture_radius > 0) {
    // Thin lens generalised to any ray: move the origin on a disk perpendicular to the ray and
    // re-aim at the point at focus_distance along the original ray.
    const Vec3 focus = r->org + r->dir * dof_.focus_distance;
    const Frame f = Frame::from_normal(r->dir);
    const Vec2 l = sample_disk_concentric(cs.lens) * dof_.aperture_radius;
    r->org = r->org + f.s * l.x + f.t * l.y;
    r->dir = normalize(focus - r->org);
  }
  if (!camera_space) to_world(&*r);
  return r;
}

void VirtualCamera::to_world(CameraRay* r) const {
  if (!rig_identity_) to_world(r, world_from_camera_);
}

void VirtualCamera::to_world(CameraRay* r, const Transform& t) const {
  {
    r->org = t.point(r->org);
    const Vec3 d = t.vector(r->dir);
    const double len = length(d);
    r->dir = d / len;
    r->dorg_du = t.vector(r->dorg_du);
    r->dorg_dv = t.vector(r->dorg_dv);
    r->ddir_du = normalized_derivative(r->dir, len, t.vector(r->ddir_du));
    r->ddir_dv = normalized_derivative(r->dir, len, t.vector(r->ddir_dv));
  }
}

std::vector<Vec2> VirtualCamera::project(const Vec3& p) const {
  // The closed form knows only the undistorted functions.
  if (!inverse_ || !coins_.empty()) return project_numeric(*this, p);
  return inverse_->project(rig_identity_ ? p : world_from_camera_.inverse().point(p));
}

namespace {

// Perpendicular offset of p from the ray, and whether p lies in front of the origin.
struct Miss {
  Vec3 e;
  bool ok = false;
  double along = 0;
};

Miss miss_at(const Camera& cam, const Vec3& p, Vec2 uv) {
  CameraSample s;
  s.uv = uv;
  auto r = cam.generate(s);
  Miss m;
  if (!r) return m;
  const Vec3 op = p - r->org;
  m.along = dot(op, r->dir);
  m.e = op - r->dir * m.along;
  m.ok = true;
  return m;
}

// Angle-like error that is scale free: |perpendicular| / distance, or a large value behind.
double angular_miss(const Miss& m, const Vec3&) {
  if (!m.ok) return kInf;
  const double perp = length(m.e);
  if (m.along <= 0) return 2.0 + perp;  // behind the origin: worse than any front miss
  return perp / std::max(m.along, 1e-300);
}

}  // namespace

std::vector<Vec2> project_numeric(const Camera& cam, const Vec3& p, int grid) {
  // 1. Coarse grid of angular misses.
  const int n = grid;
  std::vector<double> err(size_t(n) * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      err[size_t(j) * n + i] = angular_miss(miss_at(cam, p, {(i + 0.5) / n, (j + 0.5) / n}), p);

  // 2. Gauss-Newton from every local minimum of the grid.
  std::vector<Vec2> out;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double e0 = err[size_t(j) * n + i];
      if (!(e0 < 1.0)) continue;
      bool local_min = true;
      for (int dj = -1; dj <= 1 && local_min; ++dj)
        for (int di = -1; di <= 1; ++di) {
          const int a = i + di, b = j + dj;
          if ((di || dj) && a >= 0 && b >= 0 && a < n && b < n) {
            const double e1 = err[size_t(b) * n + a];
            // Strict on one side so plateaus produce a single seed.
            if (e1 < e0 || (e1 == e0 && (dj < 0 || (dj == 0 && di < 0)))) {
              local_min = false;
              break;
            }
          }
        }
      if (!local_min) continue;

      Vec2 uv{(i + 0.5) / n, (j + 0.5) / n};
      bool converged = false;
      for (int it = 0; it < 60; ++it) {
        const Miss m = miss_at(cam, p, uv);
        if (!m.ok || m.along <= 0) break;
        const double scale = std::max(m.along, 1e-12);
        if (length(m.e) / scale < 1e-12) {
          converged = true;
          break;
        }
        // Central finite differences of the miss vector (works for any camera).
        const double h = 1e-6;
        const Miss mu0 = miss_at(cam, p, {uv.x - h, uv.y}), mu1 = miss_at(cam, p, {uv.x + h, uv.y});
        const Miss mv0 = miss_at(cam, p, {uv.x, uv.y - h}), mv1 = miss_at(cam, p, {uv.x, uv.y + h});
        if (!mu0.ok || !mu1.ok || !mv0.ok || !mv1.ok) break;
        const Vec3 ju = (mu1.e - mu0.e) / (2 * h), jv = (mv1.e - mv0.e) / (2 * h);
        // Normal equations of the 3x2 least-squares step.
        const double a = dot(ju, ju), b = dot(ju, jv), c = dot(jv, jv);
        const double ru = -dot(ju, m.e), rv = -dot(jv, m.e);
        const double det = a * c - b * b;
        if (!(std::abs(det) > 1e-300)) break;
        Vec2 step{(c * ru - b * rv) / det, (a * rv - b * ru) / det};
        // Damp steps that leave the domain or grow the error.
        const double cur = length(m.e);
        double t = 1;
        for (int k = 0; k < 20; ++k, t *= 0.5) {
          Vec2 cand = uv + step * t;
          cand.x = std::clamp(cand.x, 0.0, 1.0);
          cand.y = std::clamp(cand.y, 0.0, 1.0);
          const Miss mc = miss_at(cam, p, cand);
          if (mc.ok && mc.along > 0 && length(mc.e) < cur) {
            uv = cand;
            break;
          }
        }
        if (t < 1e-5) {
          converged = length(m.e) / scale < 1e-9;
          break;
        }
      }
      if (!converged) {
        const Miss m = miss_at(cam, p, uv);
        converged = m.ok && m.along > 0 && length(m.e) / std::max(m.along, 1e-12) < 1e-9;
      }
      if (!converged) continue;
      const bool dup =
          std::any_of(out.begin(), out.end(), [&](const Vec2& q) { return length(q - uv) < 1e-6; });
      if (!dup) out.push_back(uv);
    }
  return out;
}

}  // namespace anamorph
