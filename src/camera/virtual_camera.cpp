#include "camera/virtual_camera.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "math/frame.h"
#include "math/input_limits.h"
#include "math/sampling.h"

namespace anamorph {

VirtualCamera::VirtualCamera(VirtualCameraParts parts, DepthOfField dof)
    : org_(std::move(parts.org)),
      dir_(std::move(parts.dir)),
      inverse_(std::move(parts.inverse)),
      world_from_camera_(parts.world_from_camera),
      rig_identity_(parts.world_from_camera.is_identity()),
      dof_(dof),
      description_(std::move(parts.description)),
      derivatives_(std::move(parts.derivatives)) {
  shutter_ = parts.shutter;
  if (parts.world_from_camera_close) {
    moving_ = !(parts.world_from_camera_close->matrix() == world_from_camera_.matrix());
    if (moving_) motion_ = RigidMotion(world_from_camera_, *parts.world_from_camera_close);
  }
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c)
      rig34_.m[r][c] = world_from_camera_.matrix().m[size_t(r)][size_t(c)];
  const bool rig_affine = world_from_camera_.matrix().m[3] == std::array<double, 4>{0, 0, 0, 1};
  // Rigs built from look_at are orthonormal to a few units in the last place; a scale makes
  // the finish normalize again.
  double worst = 0;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      double dot_ab = 0;
      for (int r = 0; r < 3; ++r) dot_ab += rig34_.m[r][a] * rig34_.m[r][b];
      worst = std::max(worst, std::abs(dot_ab - (a == b ? 1.0 : 0.0)));
    }
  const bool rig_rotation = rig_affine && worst < 1e-15;
  detect_linear_field();
  detect_point_origin();
  choose_kernels(rig_affine, rig_rotation);
  if (!parts.coins.empty()) {
    // (uc, vc) come from the undistorted camera: coins_ is still empty while projecting.
    coins_ = CoinField(
        parts.coins, world_from_camera_.inverse(), [this](const Vec3& p) { return project(p); },
        *org_, &coin_warnings_);
    if (!coins_.empty())
      description_ += " + " + std::to_string(parts.coins.size()) +
                      (parts.coins.size() == 1 ? " coin" : " coins");
    choose_kernels(rig_affine, rig_rotation);
  }
}

// Every way this camera makes rays, decided here once (nothing below tests a property of the
// camera to pick a path per call):
//   lens, motion or a projective rig   one ray at a time (general_ray), packets as a loop of those
//   affine field                       affine_rays<coins>: the closed form, one kernel
//   otherwise                          function_rays<point origin, coins>: the org/dir batches
//                                      (first-order origins when the directions read no more),
//                                      then the finishing pass for this rig and these directions
void VirtualCamera::choose_kernels(bool rig_affine, bool rig_rotation) {
  const bool coins = !coins_.empty();
  packet_ = nullptr;
  if (dof_.aperture_radius > 0 || moving_ || !rig_affine) return;
  if (linear_) {
    affine_ = affine_kernel();
    packet_ = coins ? &VirtualCamera::affine_rays<true> : &VirtualCamera::affine_rays<false>;
    return;
  }
  const bool point = bool(point_batch_);
  if (point)
    packet_ = coins ? &VirtualCamera::function_rays<true, true>
                    : &VirtualCamera::function_rays<true, false>;
  else
    packet_ = coins ? &VirtualCamera::function_rays<false, true>
                    : &VirtualCamera::function_rays<false, false>;
  org_batch_ = dir_->reads_org_beyond_first_order() ? &OrgFunction::eval_batch
                                                    : &OrgFunction::eval_batch_first_order;
  // Unit directions stay unit under a rig that keeps lengths (the identity is a rotation too);
  // coins deform the rays in camera space, before the rig.
  const bool unit = dir_->unit_length();
  finish_world_ = finish_kernel({point, rig_identity_, unit && rig_rotation});
  finish_camera_ = finish_kernel({point, true, unit});
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
  camera_field_ = {s0.p, s0.dpdu, s0.dpdv, d0.d, d0.dd_du, d0.dd_dv};
  const Transform& t = world_from_camera_;
  world_field_ = {t.point(s0.p),  t.vector(s0.dpdu),  t.vector(s0.dpdv),
                  t.vector(d0.d), t.vector(d0.dd_du), t.vector(d0.dd_dv)};
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
  point_batch_ = std::make_unique<SurfaceBatch>();
  for (int i = 0; i < kCameraBatch; ++i) point_batch_->set(i, s0), point_batch_->ok[i] = true;
}

std::optional<CameraRay> VirtualCamera::generate_pinhole(Vec2 uv) const {
  std::optional<CameraRay> r = generate_uncoined(uv);
  // Coins deform the ray field org/dir define (the paper: independent of the functions).
  if (r && !coins_.apply(uv, &*r)) return std::nullopt;
  return r;
}

std::optional<CameraRay> VirtualCamera::generate_uncoined(Vec2 uv) const {
  SurfaceSample s;
  DirSample d;
  // An affine field under a coin: its closed form instead of the function calls (samples no coin
  // reaches keep the exact path they have without coins).
  if (linear_ && coins_.reaches(uv))
    camera_field_.sample(uv, &s, &d);
  else if (!org_->eval(uv, &s) || !dir_->eval(uv, s, &d))
    return std::nullopt;
  const double len = length(d.d);
  // A zero-length or non-finite direction means "no ray", never NaN.
  if (!(len > 0) || !std::isfinite(len) || !is_finite(s.p)) return std::nullopt;
  CameraRay r{s.p, d.d, s.dpdu, s.dpdv, d.dd_du, d.dd_dv};
  unit_direction<true>(len, r.dir.x, r.dir.y, r.dir.z, r.ddir_du.x, r.ddir_du.y, r.ddir_du.z,
                       r.ddir_dv.x, r.ddir_dv.y, r.ddir_dv.z);
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
  if (!packet_) return general_ray(cs);
  CameraRayBatch b;
  (this->*packet_)(&cs.uv.x, &cs.uv.y, 1, &b);
  if (!b.valid[0]) return std::nullopt;
  return b.ray(0);
}

void VirtualCamera::generate_batch_any(const CameraSample* s, int n, CameraRayBatch* out) const {
  if (!packet_) {
    for (int i = 0; i < n; ++i) out->set(i, general_ray(s[i]));
    return;
  }
  alignas(64) double u[kCameraBatch], v[kCameraBatch];
  split_sample_positions(s, n, u, v);
  (this->*packet_)(u, v, n, out);
}

template <bool kCoins>
void VirtualCamera::affine_rays(const double* u, const double* v, int n,
                                CameraRayBatch* out) const {
  affine_(world_field_, u, v, n, out);
  if (!kCoins || !coins_.may_reach(u, v, n)) return;
  CameraRayBatch plain;
  affine_(camera_field_, u, v, n, &plain);
  deform_by_coins(u, v, n, &plain, out);
}

template <bool kPointOrg, bool kCoins>
void VirtualCamera::function_rays(const double* u, const double* v, int n,
                                  CameraRayBatch* out) const {
  // The functions once for all samples; samples no coin reaches finish as without coins (same
  // bits), the others in camera space, deformed, then through the rig.
  SurfaceBatch org_lanes;
  if (!kPointOrg) ((*org_).*org_batch_)(u, v, n, &org_lanes);
  const SurfaceBatch& org = kPointOrg ? *point_batch_ : org_lanes;
  DirBatch dir;
  dir_->eval_batch(u, v, n, org, &dir);
  finish_world_(rig34_, org, dir, n, out);
  if (!kCoins || !coins_.may_reach(u, v, n)) return;
  CameraRayBatch plain;
  if (finish_camera_ == finish_world_)
    plain = *out;  // no rig: the same finishing pass
  else
    finish_camera_(rig34_, org, dir, n, &plain);
  deform_by_coins(u, v, n, &plain, out);
}

void VirtualCamera::deform_by_coins(const double* u, const double* v, int n, CameraRayBatch* plain,
                                    CameraRayBatch* out) const {
  bool reached[kCameraBatch];
  coins_.apply_batch(u, v, n, plain, reached);
  for (int k = 0; k < n; ++k) {
    if (!reached[k]) continue;
    CameraRay r = plain->ray(k);
    if (plain->valid[k] && !rig_identity_) to_world(&r, world_from_camera_);
    out->set(k, plain->valid[k] ? std::optional(r) : std::nullopt);
  }
}

std::optional<CameraRay> VirtualCamera::general_ray(const CameraSample& cs) const {
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
  // Motion blur: the rig where it is at this sample's time.
  if (moving_)
    to_world(&*r, motion_.at(shutter_time(cs)));
  else if (!rig_identity_)
    to_world(&*r, world_from_camera_);
  return r;
}

void VirtualCamera::to_world(CameraRay* r, const Transform& t) const {
  r->org = t.point(r->org);
  r->dorg_du = t.vector(r->dorg_du);
  r->dorg_dv = t.vector(r->dorg_dv);
  Vec3 d = t.vector(r->dir), du = t.vector(r->ddir_du), dv = t.vector(r->ddir_dv);
  unit_direction<true>(length(d), d.x, d.y, d.z, du.x, du.y, du.z, dv.x, dv.y, dv.z);
  r->dir = d, r->ddir_du = du, r->ddir_dv = dv;
}

std::vector<Vec2> VirtualCamera::project(const Vec3& p) const {
  // The closed form knows only the undistorted functions (project_numeric inverts generate(),
  // rolling shutter and motion included).
  if (!inverse_ || !coins_.empty()) return project_numeric(*this, p);
  if (moving_ && shutter_.rolling) return project_rolling(p);
  return inverse_->project(rig_identity_ ? p : world_from_camera_.inverse().point(p));
}

std::vector<Vec2> VirtualCamera::project_near(const Vec3& p, Vec2 seed) const {
  if (inverse_ && coins_.empty()) return project(p);  // (closed form)
  if (const std::optional<Vec2> uv = project_numeric_from(*this, p, seed)) return {*uv};
  return project_numeric(*this, p);
}

std::vector<Vec2> VirtualCamera::project_rolling(const Vec3& p) const {
  const auto at_time = [&](Vec2 uv) {
    return inverse_->project(motion_.at(shutter_time({uv})).inverse().point(p));
  };
  std::vector<Vec2> out;
  for (Vec2 uv : inverse_->project(world_from_camera_.inverse().point(p))) {
    // Contracts by the image motion over the readout per unit of image (well below 1 for any
    // usable footage); a point the iteration loses is dropped.
    bool converged = false;
    for (int k = 0; k < 100 && !converged; ++k) {
      double best = kInf;
      Vec2 next;
      for (const Vec2& q : at_time(uv))
        if (length(q - uv) < best) best = length(q - uv), next = q;
      if (!(best < kInf)) break;
      converged = best < 1e-14;
      uv = next;
    }
    if (converged) out.push_back(uv);
  }
  return out;
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

// Whether grid cell (i, j) is a local minimum of err, strictly on one side so that plateaus
// produce a single seed.
bool grid_local_min(const std::vector<double>& err, int n, int i, int j) {
  const double e0 = err[size_t(j) * n + i];
  for (int dj = -1; dj <= 1; ++dj)
    for (int di = -1; di <= 1; ++di) {
      const int a = i + di, b = j + dj;
      if ((di || dj) && a >= 0 && b >= 0 && a < n && b < n) {
        const double e1 = err[size_t(b) * n + a];
        if (e1 < e0 || (e1 == e0 && (dj < 0 || (dj == 0 && di < 0)))) return false;
      }
    }
  return true;
}

// One damped Gauss-Newton step of the miss m at uv (central finite differences of the miss
// vector: works for any camera). Returns the step length factor taken (below 1e-5: stalled), or
// a negative value when no step can be computed.
double gauss_newton_step(const Camera& cam, const Vec3& p, const Miss& m, Vec2* uv) {
  const double h = 1e-6;
  const Miss mu0 = miss_at(cam, p, {uv->x - h, uv->y}), mu1 = miss_at(cam, p, {uv->x + h, uv->y});
  const Miss mv0 = miss_at(cam, p, {uv->x, uv->y - h}), mv1 = miss_at(cam, p, {uv->x, uv->y + h});
  if (!mu0.ok || !mu1.ok || !mv0.ok || !mv1.ok) return -1;
  const Vec3 ju = (mu1.e - mu0.e) / (2 * h), jv = (mv1.e - mv0.e) / (2 * h);
  // Normal equations of the 3x2 least-squares step.
  const double a = dot(ju, ju), b = dot(ju, jv), c = dot(jv, jv);
  const double ru = -dot(ju, m.e), rv = -dot(jv, m.e);
  const double det = a * c - b * b;
  if (!(std::abs(det) > 1e-300)) return -1;
  const Vec2 step{(c * ru - b * rv) / det, (a * rv - b * ru) / det};
  // Damp steps that leave the domain or grow the error.
  const double cur = length(m.e);
  double t = 1;
  for (int k = 0; k < 20; ++k, t *= 0.5) {
    Vec2 cand = *uv + step * t;
    cand.x = std::clamp(cand.x, 0.0, 1.0);
    cand.y = std::clamp(cand.y, 0.0, 1.0);
    const Miss mc = miss_at(cam, p, cand);
    if (mc.ok && mc.along > 0 && length(mc.e) < cur) {
      *uv = cand;
      break;
    }
  }
  return t;
}

// Gauss-Newton from the seed uv: the image position whose ray passes through p, if it converges.
std::optional<Vec2> refine(const Camera& cam, const Vec3& p, Vec2 uv) {
  bool converged = false;
  for (int it = 0; it < 60; ++it) {
    const Miss m = miss_at(cam, p, uv);
    if (!m.ok || m.along <= 0) break;
    const double scale = std::max(m.along, 1e-12);
    if (length(m.e) / scale < 1e-12) {
      converged = true;
      break;
    }
    const double t = gauss_newton_step(cam, p, m, &uv);
    if (t < 0) break;
    if (t < 1e-5) {
      converged = length(m.e) / scale < 1e-9;
      break;
    }
  }
  if (!converged) {
    const Miss m = miss_at(cam, p, uv);
    converged = m.ok && m.along > 0 && length(m.e) / std::max(m.along, 1e-12) < 1e-9;
  }
  if (!converged) return std::nullopt;
  return uv;
}

}  // namespace

std::optional<Vec2> project_numeric_from(const Camera& cam, const Vec3& p, Vec2 seed) {
  return refine(cam, p, {std::clamp(seed.x, 0.0, 1.0), std::clamp(seed.y, 0.0, 1.0)});
}

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
      if (!(err[size_t(j) * n + i] < 1.0) || !grid_local_min(err, n, i, j)) continue;
      const std::optional<Vec2> uv = refine(cam, p, {(i + 0.5) / n, (j + 0.5) / n});
      if (!uv) continue;
      const bool dup = std::any_of(out.begin(), out.end(),
                                   [&](const Vec2& q) { return length(q - *uv) < 1e-6; });
      if (!dup) out.push_back(*uv);
    }
  return out;
}

}  // namespace anamorph
