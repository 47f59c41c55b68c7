// Calibrated real lenses with OpenCV's models, in OpenCV's pixel units, so a render lines up
// with a photograph from the calibrated camera.
//
// Frames: OpenCV's camera looks along +Z with X right and Y down; ours looks along -z with y up,
// so (X, Y, Z) = (x, -y, -z). Pixels: OpenCV puts pixel centers at integers (column i is x = i),
// our u of column i's center is (i + 0.5) / W, so x_pixel = u W - 0.5 (W, H the calibration
// image size, by default the rendered size).
//
// opencv_pinhole (Brown-Conrady, cv::projectPoints with k1 k2 p1 p2 k3):
//   x' = X/Z, y' = Y/Z, r^2 = x'^2 + y'^2, L = 1 + k1 r^2 + k2 r^4 + k3 r^6,
//   x'' = x' L + 2 p1 x'y' + p2 (r^2 + 2 x'^2),  y'' = y' L + p1 (r^2 + 2 y'^2) + 2 p2 x'y',
//   px = fx x'' + cx,  py = fy y'' + cy.
// opencv_fisheye (Kannala-Brandt, cv::fisheye::projectPoints without skew):
//   theta = atan(r) with r = |(X/Z, Y/Z)|, theta_d = theta (1 + k1 theta^2 + k2 theta^4 +
//   k3 theta^6 + k4 theta^8), px = fx theta_d X/(Z r) + cx, py = fy theta_d Y/(Z r) + cy.
//
// These forward maps are the closed-form inverse (`project`). The ray of a pixel needs the
// distortion inverted: Newton's method on the 2x2 system (pinhole) or on theta_d(theta)
// (fisheye), restricted to the region where the map is one-to-one (beyond the radius where
// r L(r) or theta_d(theta) stops increasing a lens folds back, and such pixels get no ray).
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

// Pixel <-> image position and the calibrated intrinsics.
struct Intrinsics {
  double fx = 1, fy = 1, cx = 0, cy = 0;
  double w = 1, h = 1;  // calibration image size
  // Normalized distorted coordinates (x'', y'') of image position uv, and back.
  Vec2 distorted(Vec2 uv) const { return {(uv.x * w - 0.5 - cx) / fx, (uv.y * h - 0.5 - cy) / fy}; }
  Vec2 image(Vec2 xd) const { return {(fx * xd.x + cx + 0.5) / w, (fy * xd.y + cy + 0.5) / h}; }
};

#define ANAMORPH_INTRINSICS_PARAMS                                                            \
  {"fx", ParamType::Number,                                                                   \
   "",   "Focal length in pixels along x (OpenCV camera matrix).",                            \
   0,    kInf,                                                                                \
   {},   true},                                                                               \
      {"fy", ParamType::Number, "", "Focal length in pixels along y.", 0, kInf, {}, true},    \
      {"cx", ParamType::Number, "none",                                                       \
       "Principal point x in pixels (pixel centers at integers). Default: (width - 1) / 2."}, \
      {"cy", ParamType::Number, "none",                                                       \
       "Principal point y in pixels. Default: (height - 1) / 2."},                            \
  {                                                                                           \
    "calibration_size", ParamType::Vec2, "none",                                              \
        "[width, height] of the calibration images, when rendering at another resolution of " \
        "the same aspect. Default: the rendered size.",                                       \
        1, kInf                                                                               \
  }

Intrinsics read_intrinsics(const ParamValues& v, const ImageInfo& img) {
  Intrinsics k;
  k.w = img.width, k.h = img.height;
  if (v.has("calibration_size")) {
    const Vec2 s = v.vec2("calibration_size");
    if (std::abs(s.x / s.y - img.aspect()) > 1e-3 * img.aspect())
      throw ParamError("calibration_size",
                       fmt::format("calibration_size has aspect {:g} but the image has {:g}",
                                   s.x / s.y, img.aspect()));
    k.w = s.x, k.h = s.y;
  }
  k.fx = v.number("fx"), k.fy = v.number("fy");
  k.cx = v.has("cx") ? v.number("cx") : (k.w - 1) / 2;
  k.cy = v.has("cy") ? v.number("cy") : (k.h - 1) / 2;
  return k;
}

// First r in (0, limit] where f(r) stops increasing, or `limit`; f' given by `slope`.
template <class Slope>
double monotone_limit(Slope slope, double limit) {
  const int n = 20000;
  double prev = 0;
  for (int i = 1; i <= n; ++i) {
    const double r = limit * i / n;
    if (!(slope(r) > 0)) {
      double lo = prev, hi = r;  // slope > 0 at lo, <= 0 at hi
      for (int j = 0; j < 80; ++j) {
        const double m = 0.5 * (lo + hi);
        (slope(m) > 0 ? lo : hi) = m;
      }
      return lo;
    }
    prev = r;
  }
  return limit;
}

// --- opencv_pinhole --------------------------------------------------------------------------

struct BrownConrady {
  double k1 = 0, k2 = 0, k3 = 0, p1 = 0, p2 = 0;
  double r_max = kInf;  // undistorted radius where r L(r) stops increasing
  double reach = kInf;  // bound on |distorted| for undistorted radius <= r_max

  void set_limits(double r) {
    r_max = r;
    if (!std::isfinite(r)) return;
    const double r2 = r * r;
    // r L(r) increases up to r_max; the tangential terms are at most 4 (|p1| + |p2|) r^2.
    reach = r * (1 + r2 * (k1 + r2 * (k2 + r2 * k3))) + 4 * (std::abs(p1) + std::abs(p2)) * r2;
  }

  // Distorted point (ox, oy) of undistorted (x, y) and the Jacobian d(x'')/d(x') as columns
  // (jxx, jxy), (jyx, jyy); scalar arguments so batch kernels vectorize it.
  [[gnu::always_inline]] void distort_lane(double x, double y, double* ox, double* oy, double* jxx,
                                           double* jxy, double* jyx, double* jyy) const {
    const double r2 = x * x + y * y;
    const double L = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
    const double dL = k1 + r2 * (2 * k2 + 3 * k3 * r2);  // dL / d(r^2)
    *ox = x * L + 2 * p1 * x * y + p2 * (r2 + 2 * x * x);
    *oy = y * L + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y;
    const double xy = 2 * x * y * dL + 2 * p1 * x + 2 * p2 * y;
    *jxx = L + 2 * x * x * dL + 2 * p1 * y + 6 * p2 * x, *jxy = xy;
    *jyx = xy, *jyy = L + 2 * y * y * dL + 6 * p1 * y + 2 * p2 * x;
  }
  Vec2 distort(Vec2 x, Vec2* jx, Vec2* jy) const {
    Vec2 o, a, b;
    distort_lane(x.x, x.y, &o.x, &o.y, &a.x, &a.y, &b.x, &b.y);
    *jx = a, *jy = b;
    return o;
  }

  bool valid(Vec2 x, Vec2 jx, Vec2 jy) const {
    return x.x * x.x + x.y * x.y <= r_max * r_max && jx.x * jy.y - jy.x * jx.y > 0;
  }
};

// Newton's method for the undistorted x with distort(x) = target, for a batch: every lane takes
// exactly the steps of the one-sample method, the batch iterates until its last lane finishes,
// and lanes that are done are masked (selects, with divisions made safe so nothing traps), so
// the arithmetic vectorizes. The line search evaluates the Jacobian with the value, so an
// accepted point is not distorted a second time. Masks are doubles (1 or 0): bool stores from
// double lanes would keep the loops scalar.
struct NewtonLanes {
  static constexpr int N = kCameraBatch;
  double tx[N], ty[N];                    // targets
  double px[N], py[N];                    // current points
  double dx[N], dy[N];                    // distort(p)
  double jxx[N], jxy[N], jyx[N], jyy[N];  // its Jacobian: columns (jxx, jxy), (jyx, jyy)
  double sx[N], sy[N], err[N], t[N];      // Newton step, residual, line-search factor
  double qdx[N], qdy[N], qjxx[N], qjxy[N], qjyx[N], qjyy[N];
  double act[N], acc[N], ok[N];  // still iterating, step accepted, converged and valid
  double pend[N];                // still searching / needs its point distorted
};

// Whether any of n masks is set: a loop of its own, since a floating-point sum in the lane
// loops would keep them scalar (adding in another order changes the result).
[[gnu::always_inline]] inline bool any_set(const double* mask, int n) {
  bool any = false;
  for (int i = 0; i < n; ++i) any |= mask[i] != 0;
  return any;
}

#define ANAMORPH_LANES [[gnu::always_inline]] inline  // (each step of the kernel below)

// The starting points: the radial term inverted to first order, x = x'' / L(|x''|^2) (where
// that stays inside the fold; the target itself otherwise), and their distortion.
ANAMORPH_LANES void undistort_start(const BrownConrady& D, NewtonLanes& __restrict S, int n) {
  const double reach2 = D.reach * D.reach, rmax2 = D.r_max * D.r_max;
  for (int i = 0; i < n; ++i) {
    // Beyond what any point inside the fold reaches there is nothing to find.
    S.act[i] = S.tx[i] * S.tx[i] + S.ty[i] * S.ty[i] <= reach2 ? 1.0 : 0.0;
    S.ok[i] = 0;
    const double r2 = S.tx[i] * S.tx[i] + S.ty[i] * S.ty[i];
    const double L = 1 + r2 * (D.k1 + r2 * (D.k2 + r2 * D.k3));
    const bool scaled = (L > 0.5) & (r2 <= rmax2 * L * L);
    const double g = 1 / (scaled ? L : 1.0);
    S.px[i] = S.tx[i] * g, S.py[i] = S.ty[i] * g;
    D.distort_lane(S.px[i], S.py[i], &S.dx[i], &S.dy[i], &S.jxx[i], &S.jxy[i], &S.jyx[i],
                   &S.jyy[i]);
  }
}

// Convergence test and the Newton step of every live lane.
ANAMORPH_LANES void newton_steps(const BrownConrady& D, NewtonLanes& __restrict S, int n) {
  const double rmax2 = D.r_max * D.r_max;
  for (int i = 0; i < n; ++i) {
    const double fx = S.dx[i] - S.tx[i], fy = S.dy[i] - S.ty[i];
    const double e = std::abs(fx) + std::abs(fy);
    // (Masks as 0/1 doubles combined by products: GCC turned the bool version into branches.)
    const double live = S.act[i];
    const double tol = 1e-14 * (1 + std::abs(S.tx[i]) + std::abs(S.ty[i]));
    const double conv = live * (e < tol ? 1.0 : 0.0);
    const double det = S.jxx[i] * S.jyy[i] - S.jyx[i] * S.jxy[i];
    const double good =
        (S.px[i] * S.px[i] + S.py[i] * S.py[i] <= rmax2 ? 1.0 : 0.0) * (det > 0 ? 1.0 : 0.0);
    S.ok[i] = conv != 0 ? good : S.ok[i];
    const double step = (live - conv) * (std::abs(det) > 1e-300 ? 1.0 : 0.0);
    const double idet = 1 / (step != 0 ? det : 1.0);
    S.sx[i] = (S.jyy[i] * fx - S.jyx[i] * fy) * idet;
    S.sy[i] = (-S.jxy[i] * fx + S.jxx[i] * fy) * idet;
    S.err[i] = e, S.t[i] = 1, S.acc[i] = 0;
    S.act[i] = step;
  }
}

// Halves steps that do not reduce the residual (folds, large distortion).
ANAMORPH_LANES void line_search(const BrownConrady& D, NewtonLanes& __restrict S, int n) {
  for (int k = 0; k < 20; ++k) {
    for (int i = 0; i < n; ++i) {
      const double search = S.act[i] * (1 - S.acc[i]);
      D.distort_lane(S.px[i] - S.sx[i] * S.t[i], S.py[i] - S.sy[i] * S.t[i], &S.qdx[i], &S.qdy[i],
                     &S.qjxx[i], &S.qjxy[i], &S.qjyx[i], &S.qjyy[i]);
      const double lower =
          std::abs(S.qdx[i] - S.tx[i]) + std::abs(S.qdy[i] - S.ty[i]) < S.err[i] ? 1.0 : 0.0;
      const double take = search * lower, halve = search - take;
      S.dx[i] = take != 0 ? S.qdx[i] : S.dx[i], S.dy[i] = take != 0 ? S.qdy[i] : S.dy[i];
      S.jxx[i] = take != 0 ? S.qjxx[i] : S.jxx[i], S.jxy[i] = take != 0 ? S.qjxy[i] : S.jxy[i];
      S.jyx[i] = take != 0 ? S.qjyx[i] : S.jyx[i], S.jyy[i] = take != 0 ? S.qjyy[i] : S.jyy[i];
      S.acc[i] = take != 0 ? 1.0 : S.acc[i];
      S.t[i] = halve != 0 ? S.t[i] * 0.5 : S.t[i];
      S.pend[i] = halve;
    }
    if (!any_set(S.pend, n)) break;
  }
}

// Moves every live lane by its (damped) step; lanes whose line search ran out of halvings get
// their point distorted where it landed.
ANAMORPH_LANES void take_steps(const BrownConrady& D, NewtonLanes& __restrict S, int n) {
  for (int i = 0; i < n; ++i) {
    const double live = S.act[i];
    const double nx = S.px[i] - S.sx[i] * S.t[i], ny = S.py[i] - S.sy[i] * S.t[i];
    S.px[i] = live != 0 ? nx : S.px[i], S.py[i] = live != 0 ? ny : S.py[i];
    const double finite = nx * 0 + ny * 0 == 0 ? 1.0 : 0.0;
    S.act[i] = live * finite;
    S.pend[i] = live * finite * (1 - S.acc[i]);
  }
  if (!any_set(S.pend, n)) return;  // (rare: a line search that ran out of halvings)
  for (int i = 0; i < n; ++i) {
    // The smallest step, taken unchecked: distort where it landed.
    const bool redo = S.act[i] * (1 - S.acc[i]) != 0;
    D.distort_lane(S.px[i], S.py[i], &S.qdx[i], &S.qdy[i], &S.qjxx[i], &S.qjxy[i], &S.qjyx[i],
                   &S.qjyy[i]);
    S.dx[i] = redo ? S.qdx[i] : S.dx[i], S.dy[i] = redo ? S.qdy[i] : S.dy[i];
    S.jxx[i] = redo ? S.qjxx[i] : S.jxx[i], S.jxy[i] = redo ? S.qjxy[i] : S.jxy[i];
    S.jyx[i] = redo ? S.qjyx[i] : S.jyx[i], S.jyy[i] = redo ? S.qjyy[i] : S.jyy[i];
  }
}

ANAMORPH_LANES void undistort_kernel(const BrownConrady& bc, NewtonLanes& __restrict S, int n) {
  const BrownConrady D = bc;
  undistort_start(D, S, n);
  for (int it = 0; it < 50; ++it) {
    newton_steps(D, S, n);
    if (!any_set(S.act, n)) break;
    line_search(D, S, n);
    take_steps(D, S, n);
  }
}

#undef ANAMORPH_LANES

// The rays of the undistorted points: d = (x', -y', -1) and, from the inverse Jacobian,
// d(x')/du = J^-1 (w / fx, 0), d(x')/dv = J^-1 (0, h / fy). One division per lane, arrays
// written directly: this loop vectorizes (through DirBatch::set it cost a quarter of the
// camera's time).
[[gnu::always_inline]] inline void pinhole_kernel(const Intrinsics& in,
                                                  const NewtonLanes& __restrict S, int n,
                                                  DirBatch* __restrict out) {
  const double su = in.w / in.fx, sv = in.h / in.fy;
  for (int i = 0; i < n; ++i) {
    const double idet = 1 / (S.jxx[i] * S.jyy[i] - S.jyx[i] * S.jxy[i]);
    out->d[0][i] = S.px[i], out->d[1][i] = -S.py[i], out->d[2][i] = -1;
    out->du[0][i] = S.jyy[i] * idet * su, out->du[1][i] = S.jxy[i] * idet * su;
    out->du[2][i] = 0;
    out->dv[0][i] = -S.jyx[i] * idet * sv, out->dv[1][i] = -S.jxx[i] * idet * sv;
    out->dv[2][i] = 0;
  }
  for (int i = 0; i < n; ++i) out->ok[i] = S.ok[i] != 0;
}

// The whole direction batch in one clone: targets (pixels to normalized distorted coordinates),
// Newton, directions.
ANAMORPH_KERNEL_BODY void pinhole_dirs_body(const Intrinsics& in, const BrownConrady& D,
                                            const double* u, const double* v, int n,
                                            DirBatch* out) {
  with_trip_count<kCameraBatch>(
      n, [&](auto m) __attribute__((always_inline)) {
        NewtonLanes S;
        const Intrinsics K = in;
        for (int i = 0; i < m; ++i) {
          const Vec2 t = K.distorted({u[i], v[i]});
          S.tx[i] = t.x, S.ty[i] = t.y;
        }
        undistort_kernel(D, S, m);
        pinhole_kernel(K, S, m, out);
      });
}
constexpr simd::Kernel<pinhole_dirs_body> pinhole_dirs;

class PinholeDir final : public DirFunction {
 public:
  PinholeDir(Intrinsics k, BrownConrady d) : k_(k), d_(d) {}
  // One sample: a batch of one, so single rays and packets give the same bits.
  bool eval(Vec2 uv, const SurfaceSample& org, DirSample* out) const override {
    return eval_as_batch_of_one(*this, uv, org, out);
  }
  void eval_batch(const double* u, const double* v, int n, const SurfaceBatch&,
                  DirBatch* out) const override {
    pinhole_dirs(k_, d_, u, v, n, out);
  }

 private:
  Intrinsics k_;
  BrownConrady d_;
};

const ParamSpec kPinholeParams[] = {
    ANAMORPH_LOOK_AT_PARAMS,
    ANAMORPH_INTRINSICS_PARAMS,
    {"k1", ParamType::Number, "0", "Radial distortion coefficient k1."},
    {"k2", ParamType::Number, "0", "Radial distortion coefficient k2."},
    {"k3", ParamType::Number, "0", "Radial distortion coefficient k3."},
    {"p1", ParamType::Number, "0", "Tangential distortion coefficient p1."},
    {"p2", ParamType::Number, "0", "Tangential distortion coefficient p2."},
};

VirtualCameraParts create_pinhole(const ParamValues& v, const ImageInfo& img) {
  check_params(kPinholeParams, v);
  const Intrinsics k = read_intrinsics(v, img);
  BrownConrady d;
  d.k1 = v.number("k1"), d.k2 = v.number("k2"), d.k3 = v.number("k3");
  d.p1 = v.number("p1"), d.p2 = v.number("p2");
  // d(r L(r))/dr = L + 2 r^2 dL/d(r^2); scanned up to r = 1e3 (89.9 degrees).
  const double r_max = monotone_limit(
      [&](double r) {
        const double r2 = r * r;
        return 1 + r2 * (3 * d.k1 + r2 * (5 * d.k2 + 7 * d.k3 * r2));
      },
      1e3);
  d.set_limits(r_max < 1e3 ? r_max : kInf);
  VirtualCameraParts p;
  p.org = make_point_org({});
  p.dir = std::make_unique<PinholeDir>(k, d);
  p.world_from_camera = rig_from_look_at(v);
  p.description = "opencv_pinhole (org point + dir Brown-Conrady undistorted plane)";
  p.inverse = make_inverse([k, d](const Vec3& q) -> std::vector<Vec2> {
    if (!(q.z < 0)) return {};
    const Vec2 x{q.x / -q.z, -q.y / -q.z};  // OpenCV's (X/Z, Y/Z)
    Vec2 jx, jy;
    const Vec2 xd = d.distort(x, &jx, &jy);
    if (!d.valid(x, jx, jy)) return {};
    Vec2 uv = k.image(xd);
    if (!clamp_to_image(&uv)) return {};
    return {uv};
  });
  return p;
}

// --- opencv_fisheye --------------------------------------------------------------------------

struct KannalaBrandt {
  double k1 = 0, k2 = 0, k3 = 0, k4 = 0;
  double theta_max = kPi;  // where theta_d(theta) stops increasing, at most pi

  double theta_d(double t, double* slope) const {
    const double t2 = t * t;
    *slope = 1 + t2 * (3 * k1 + t2 * (5 * k2 + t2 * (7 * k3 + t2 * 9 * k4)));
    return t * (1 + t2 * (k1 + t2 * (k2 + t2 * (k3 + t2 * k4))));
  }
};

// theta with theta_d(theta) = td by safeguarded Newton on [0, theta_max] (a step that leaves the
// bracket bisects), then the direction at polar angle theta (radial_direction), for a batch:
// masked lanes as in undistort_kernel, and the one-sample path is a batch of one.
[[gnu::always_inline]] inline void kb_kernel(const KannalaBrandt& kb, const Intrinsics& in,
                                             double top, const double* __restrict u,
                                             const double* __restrict v, int n,
                                             DirBatch* __restrict out) {
  const KannalaBrandt D = kb;
  const Intrinsics K = in;
  constexpr int N = kCameraBatch;
  double a[N], b[N], td[N], x[N], lo[N], hi[N], slope[N], act[N], fresh[N], ok[N];
  for (int i = 0; i < n; ++i) {
    const Vec2 xd = K.distorted({u[i], v[i]});
    // Our image plane (a right, b up) is OpenCV's (x, -y).
    a[i] = xd.x, b[i] = -xd.y;
    td[i] = std::sqrt(xd.x * xd.x + xd.y * xd.y);
    ok[i] = ((td[i] >= 0) & (td[i] <= top)) ? 1.0 : 0.0;
    act[i] = ok[i], fresh[i] = 0, slope[i] = 1;
    x[i] = td[i] < D.theta_max ? td[i] : D.theta_max;
    lo[i] = 0, hi[i] = D.theta_max;
  }
  for (int it = 0; it < 200; ++it) {
    for (int i = 0; i < n; ++i) {
      const bool live = act[i] != 0;
      double sl;
      const double f = D.theta_d(x[i], &sl) - td[i];
      slope[i] = live ? sl : slope[i];
      fresh[i] = live ? 1.0 : fresh[i];
      hi[i] = (live & (f > 0)) ? x[i] : hi[i];
      lo[i] = (live & !(f > 0)) ? x[i] : lo[i];
      const bool done = std::abs(f) < 1e-15 * (1 + td[i]);
      double nx = x[i] - f / sl;
      nx = ((nx > lo[i]) & (nx < hi[i])) ? nx : 0.5 * (lo[i] + hi[i]);
      const bool move = live & !done & (nx != x[i]);
      x[i] = move ? nx : x[i];
      fresh[i] = move ? 0.0 : fresh[i];
      act[i] = move ? 1.0 : 0.0;
    }
    if (!any_set(act, n)) break;
  }
  const double su = K.w / K.fx, sv = -K.h / K.fy;
  for (int i = 0; i < n; ++i) {
    double sl;
    D.theta_d(x[i], &sl);
    const double dtheta = 1 / (fresh[i] != 0 ? slope[i] : sl);  // theta(rho) has slope 1/theta_d'
    double st, ct;
    sincos_poly(x[i], &st, &ct);
    bool axis;  // on the axis theta must be 0
    const RadialDirection rd = radial_lane(a[i], b[i], st, ct, dtheta, &axis);
    // (The comparison on a selected value, not under `axis`: a conditional compare may trap and
    // would stay a branch.)
    ok[i] = (axis ? std::abs(x[i]) : 0.0) > 1e-9 ? 0.0 : ok[i];
    out->d[0][i] = rd.d.x, out->d[1][i] = rd.d.y, out->d[2][i] = rd.d.z;
    out->du[0][i] = rd.dd_da.x * su, out->du[1][i] = rd.dd_da.y * su;
    out->du[2][i] = rd.dd_da.z * su;
    out->dv[0][i] = rd.dd_db.x * sv, out->dv[1][i] = rd.dd_db.y * sv;
    out->dv[2][i] = rd.dd_db.z * sv;
  }
  for (int i = 0; i < n; ++i) out->ok[i] = ok[i] != 0;
}

ANAMORPH_KERNEL_BODY void kb_dirs_body(const KannalaBrandt& D, const Intrinsics& K, double top,
                                       const double* u, const double* v, int n, DirBatch* out) {
  with_trip_count<kCameraBatch>(
      n, [&](auto m) __attribute__((always_inline)) { kb_kernel(D, K, top, u, v, m, out); });
}
constexpr simd::Kernel<kb_dirs_body> kb_dirs;

class FisheyeCvDir final : public DirFunction {
 public:
  FisheyeCvDir(Intrinsics k, KannalaBrandt d) : k_(k), d_(d) {
    double slope;
    top_ = d_.theta_d(d_.theta_max, &slope);
  }
  // One sample: a batch of one, so single rays and packets give the same bits.
  bool eval(Vec2 uv, const SurfaceSample& org, DirSample* out) const override {
    return eval_as_batch_of_one(*this, uv, org, out);
  }
  void eval_batch(const double* u, const double* v, int n, const SurfaceBatch&,
                  DirBatch* out) const override {
    kb_dirs(d_, k_, top_, u, v, n, out);
  }
  bool unit_length() const override { return true; }  // (sin t a / rho, sin t b / rho, -cos t)

 private:
  Intrinsics k_;
  KannalaBrandt d_;
  double top_;  // theta_d(theta_max): the largest distorted radius
};

const ParamSpec kFisheyeParams[] = {
    ANAMORPH_LOOK_AT_PARAMS,
    ANAMORPH_INTRINSICS_PARAMS,
    {"k1", ParamType::Number, "0", "Kannala-Brandt coefficient k1 (of theta^3)."},
    {"k2", ParamType::Number, "0", "Kannala-Brandt coefficient k2 (of theta^5)."},
    {"k3", ParamType::Number, "0", "Kannala-Brandt coefficient k3 (of theta^7)."},
    {"k4", ParamType::Number, "0", "Kannala-Brandt coefficient k4 (of theta^9)."},
};

VirtualCameraParts create_fisheye_cv(const ParamValues& v, const ImageInfo& img) {
  check_params(kFisheyeParams, v);
  const Intrinsics k = read_intrinsics(v, img);
  KannalaBrandt d;
  d.k1 = v.number("k1"), d.k2 = v.number("k2"), d.k3 = v.number("k3"), d.k4 = v.number("k4");
  d.theta_max = monotone_limit(
      [&](double t) {
        double s;
        d.theta_d(t, &s);
        return s;
      },
      kPi);
  VirtualCameraParts p;
  p.org = make_point_org({});
  p.dir = std::make_unique<FisheyeCvDir>(k, d);
  p.world_from_camera = rig_from_look_at(v);
  p.description = "opencv_fisheye (org point + dir Kannala-Brandt sphere)";
  p.inverse = make_inverse([k, d](const Vec3& q) -> std::vector<Vec2> {
    Vec2 az;
    const double theta = polar_angle(q, &az);
    if (!(length(q) > 0) || !(theta <= d.theta_max)) return {};
    double slope;
    const double td = d.theta_d(theta, &slope);
    Vec2 uv = k.image({td * az.x, -td * az.y});
    if (!clamp_to_image(&uv)) return {};
    return {uv};
  });
  return p;
}

}  // namespace

const PresetInfo kOpenCvPinholePreset{
    "opencv_pinhole",
    "A calibrated camera with OpenCV's pinhole model and Brown-Conrady distortion (k1 k2 k3 "
    "radial, p1 p2 tangential), in OpenCV pixel units. org = point, dir = the undistorted image "
    "plane (Newton's method per pixel).",
    kPinholeParams, create_pinhole};

const PresetInfo kOpenCvFisheyePreset{
    "opencv_fisheye",
    "A calibrated fisheye with OpenCV's Kannala-Brandt model (cv::fisheye, k1..k4), in OpenCV "
    "pixel units. org = point, dir = sphere by the inverted theta_d(theta) (Newton per pixel).",
    kFisheyeParams, create_fisheye_cv};

}  // namespace anamorph
