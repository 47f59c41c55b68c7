// Centers of interest: the weight function, the coins' parameter table, and CoinField, which
// finds each coin's (uc, vc) and deforms samples using only the coins whose radius reaches them
// (a uniform grid over (u, v)).
#include "camera/coins.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "camera/camera.h"
#include "camera/virtual_camera.h"
#include "math/simd.h"

namespace anamorph {

// ---- the weight --------------------------------------------------------------------------------

namespace {

// The Gaussian kernel's width in units of the radius. Narrow enough that truncation and the
// C1 correction below change little (exp(-1 / (2 sigma^2)) = 1.7%).
constexpr double kGaussSigma = 0.35;
constexpr double kGaussA = 1 / (2 * kGaussSigma * kGaussSigma);
const double kGaussG1 = std::exp(-kGaussA);
const double kGaussInvNorm = 1 / (1 - kGaussG1 * (1 + kGaussA));

// The three factors, inline for the per-sample loop.
inline KernelValue kernel(CoinFalloff f, double x) {
  if (!(x < 1)) return {};
  const double r = 1 - x;
  switch (f) {
    case CoinFalloff::Smooth:  // (1 - t^2)^3: C2, value and two derivatives vanish at t = 1
      return {r * r * r, -3 * r * r, 6 * r};
    case CoinFalloff::Quadratic:  // (1 - t^2)^2: C1, the minimal smoothness, broadest profile
      return {r * r, -2 * r, 2};
    case CoinFalloff::Gaussian: {
      // exp(-a x) minus its first-order Taylor polynomial at x = 1, renormalized: value and
      // slope vanish at the radius (C1), and it still declines monotonically because the
      // exponential's slope only grows toward x = 1.
      const double g = std::exp(-kGaussA * x);
      return {(g - kGaussG1 - kGaussA * kGaussG1 * r) * kGaussInvNorm,
              kGaussA * (kGaussG1 - g) * kGaussInvNorm, kGaussA * kGaussA * g * kGaussInvNorm};
    }
  }
  return {};
}

// Schlick's bias function: B(0) = 0, B(1) = 1, increasing, smooth; B = y for s = 1.
inline KernelValue stiffness(double s, double y) {
  const double q = 1 / (1 + (s - 1) * y);
  return {s * y * q, s * q * q, -2 * s * (s - 1) * q * q * q};
}

inline KernelValue distance(double z) {
  const double q = 1 / (1 + z * z);
  return {2 * z * q, 2 * (1 - z * z) * q * q, 4 * z * (z * z - 3) * q * q * q};
}

}  // namespace

KernelValue coin_kernel(CoinFalloff f, double x) { return kernel(f, x); }
KernelValue coin_stiffness(double s, double y) { return stiffness(s, y); }
KernelValue coin_distance(double z) { return distance(z); }

double coin_weight(double m, double l, double d, double s, double radius, double lc,
                   CoinFalloff f) {
  const KernelValue k = coin_kernel(f, (d * d) / (radius * radius));
  if (k.k == 0) return 0;
  return m * coin_stiffness(s, k.k).k * coin_distance((l * l) / (lc * lc)).k;
}

double coin_min_strength(double stiffness, CoinFalloff f) {
  // h(t) = (t g)' = g + t g' = F(x) + 2 x F'(x) with x = t^2; the radial Jacobian of the
  // repelled image is 1 + |m| h(t), so |m| must stay below 1 / max(-h).
  double worst = 0;
  constexpr int n = 4096;
  for (int i = 0; i <= n; ++i) {
    const double t = double(i) / n, x = t * t;
    const KernelValue k = coin_kernel(f, x);
    const KernelValue b = coin_stiffness(stiffness, k.k);
    worst = std::max(worst, -(b.k + 2 * x * b.dk * k.dk));
  }
  // 1% margin for the sampling of h.
  return worst > 0.99 ? -0.99 / worst : -1.0;
}

// ---- parameters --------------------------------------------------------------------------------

namespace {

constexpr std::string_view kAffects[] = {"org", "dir", "both"};
constexpr std::string_view kFalloffs[] = {"smooth", "quadratic", "gaussian"};

// clang-format off
const ParamSpec kCoinParams[] = {
    {"position", ParamType::Vec3, "", "The center of interest, a point in world space."},
    {"strength", ParamType::Number, "0.5",
     "m: the fraction of the way to the coin that the image surface (or direction) moves at "
     "(uc, vc); the local zoom there is 1 / (1 - m) (squared with affects = \"both\" on a "
     "pinhole). 0 = no effect; negative repels (a local reduction), down to a limit that "
     "depends on stiffness and falloff (no fold-over).",
     -1, 1},
    {"stiffness", ParamType::Number, "1",
     "s: a low stiffness (flexible surface) deforms significantly only very close to (uc, vc), "
     "a high one deforms the whole radius almost evenly.",
     0, kInf, {}, true},
    {"radius", ParamType::Number, "0.25",
     "R: radius of influence in image parameter space (u, v in [0, 1]); beyond it the coin has "
     "exactly no effect.",
     0, 2, {}, true},
    {"affects", ParamType::String, "\"both\"",
     "What the coin deforms: the ray origins (org), the ray directions (dir) or both.",
     -kInf, kInf, kAffects},
    {"falloff", ParamType::String, "\"smooth\"",
     "Kernel K over t = d / R: smooth = (1 - t^2)^3 (C2), quadratic = (1 - t^2)^2 (C1, "
     "broadest), gaussian = exp(-t^2 / (2 * 0.35^2)) made C1 at the radius.",
     -kInf, kInf, kFalloffs},
};
// clang-format on

}  // namespace

std::span<const ParamSpec> coin_params() { return kCoinParams; }

Coin coin_from_params(const ParamValues& v) {
  check_params(kCoinParams, v);
  Coin c;
  c.position = v.vec3("position");
  c.strength = v.number("strength");
  c.stiffness = v.number("stiffness");
  c.radius = v.number("radius");
  const std::string& a = v.string("affects");
  c.affects = a == "org" ? CoinAffects::Org : a == "dir" ? CoinAffects::Dir : CoinAffects::Both;
  const std::string& f = v.string("falloff");
  c.falloff = f == "quadratic"  ? CoinFalloff::Quadratic
              : f == "gaussian" ? CoinFalloff::Gaussian
                                : CoinFalloff::Smooth;
  // (The limit is negative: a strength >= 0 needs no search for it; the solver builds coins often.)
  const double lo = c.strength < 0 ? coin_min_strength(c.stiffness, c.falloff) : -1;
  if (c.strength < lo)
    throw ParamError("strength",
                     fmt::format("strength {} would fold the image over around the coin (with "
                                 "stiffness {} and falloff \"{}\" the most negative strength is "
                                 "{:.3f})",
                                 c.strength, c.stiffness, f, lo));
  return c;
}

Coin make_coin(std::string_view toml_text) {
  return coin_from_params(params_from_toml(kCoinParams, toml_text));
}

// ---- CoinField ---------------------------------------------------------------------------------

namespace {

// Cell index of a coordinate; NaN and out-of-range values go to the nearest edge cell, which is
// safe because every disk has its center inside [0,1]^2 (clamping moves a point closer to it).
int cell_index(double t, int n) {
  const double c = t > 0 ? (t < 1 ? t : 1) : 0;
  return std::min(int(c * n), n - 1);
}

}  // namespace

CoinField::CoinField(std::span<const Coin> coins, const Transform& camera_from_world,
                     const std::function<std::vector<Vec2>(const Vec3&)>& project_world,
                     const OrgFunction& org, std::vector<std::string>* warnings) {
  const auto warn = [&](std::string msg) {
    if (warnings) warnings->push_back(std::move(msg));
  };
  for (size_t i = 0; i < coins.size(); ++i) {
    // Dropped, not weighted by zero: a strength-0 coin leaves every ray bit-identical.
    if (coins[i].strength == 0) continue;
    if (add_sites(int(i), coins[i], camera_from_world.point(coins[i].position),
                  project_world(coins[i].position), org, warn) == 0)
      warn(fmt::format(
          "coin[{}]: the camera does not see position [{}, {}, {}], so the coin has no effect", i,
          coins[i].position.x, coins[i].position.y, coins[i].position.z));
  }
  if (sites_.empty()) return;
  for (const CoinSite& s : sites_) {
    disks_.push_back({s.uv.x, s.uv.y, 1 / (s.radius * s.radius)});
    inv_lc2_.push_back(1 / (s.lc * s.lc));
  }
  build_grid();
  if (const std::string w = overlap_warning(); !w.empty()) warn(w);
}

// A site for each image position uvs (the coin's appearances) that the image shows and where
// the coin lies off the image surface; returns how many.
int CoinField::add_sites(int index, const Coin& c, const Vec3& pc, const std::vector<Vec2>& uvs,
                         const OrgFunction& org, const std::function<void(std::string)>& warn) {
  int seen = 0;
  for (Vec2 uv : uvs) {
    constexpr double tol = 1e-9;
    if (!(uv.x >= -tol && uv.x <= 1 + tol && uv.y >= -tol && uv.y <= 1 + tol)) continue;
    uv = {std::clamp(uv.x, 0.0, 1.0), std::clamp(uv.y, 0.0, 1.0)};
    SurfaceSample s;
    if (!org.eval(uv, &s) || !is_finite(s.p)) continue;
    const double lc = length(pc - s.p);
    if (!(lc > 0)) {
      warn(
          fmt::format("coin[{}]: lies on the image surface at (u, v) = ({:.4f}, {:.4f}), so "
                      "there is nothing to attract there; that appearance has no effect",
                      index, uv.x, uv.y));
      continue;
    }
    CoinSite site;
    site.coin = index;
    site.uv = uv;
    site.radius = c.radius;
    site.lc = lc;
    site.strength = c.strength;
    site.stiffness = c.stiffness;
    site.affects = c.affects;
    site.falloff = c.falloff;
    site.p_camera = pc;
    sites_.push_back(site);
    ++seen;
  }
  return seen;
}

// Calls f(cell) for every cell of an n x n grid that the open disk of site s reaches.
template <class F>
static void cells_of(const CoinSite& s, int n, F&& f) {
  const int i0 = cell_index(s.uv.x - s.radius, n), i1 = cell_index(s.uv.x + s.radius, n);
  const int j0 = cell_index(s.uv.y - s.radius, n), j1 = cell_index(s.uv.y + s.radius, n);
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i) {
      // Closest point of the cell to the center; keep cells the open disk reaches.
      const double cu = std::clamp(s.uv.x, double(i) / n, double(i + 1) / n);
      const double cv = std::clamp(s.uv.y, double(j) / n, double(j + 1) / n);
      const double du = cu - s.uv.x, dv = cv - s.uv.y;
      if (du * du + dv * dv < s.radius * s.radius) f(j * n + i);
    }
}

// Cells about as large as the median radius: a disk then covers a handful of cells and a cell
// holds only the coins that can reach it.
void CoinField::build_grid() {
  std::vector<double> radii;
  for (const CoinSite& s : sites_) radii.push_back(s.radius);
  std::nth_element(radii.begin(), radii.begin() + radii.size() / 2, radii.end());
  // (Clamped before the conversion: a radius of 1e-29 would make 1 / r overflow an int.)
  grid_ = int(std::clamp(std::ceil(1 / radii[radii.size() / 2]), 1.0, 512.0));
  const int n = grid_;
  cell_start_.assign(size_t(n) * n + 1, 0);
  for (const CoinSite& s : sites_) cells_of(s, n, [&](int c) { ++cell_start_[size_t(c) + 1]; });
  for (size_t c = 1; c < cell_start_.size(); ++c) cell_start_[c] += cell_start_[c - 1];
  cell_items_.resize(cell_start_.back());
  std::vector<uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (uint32_t k = 0; k < sites_.size(); ++k)
    cells_of(sites_[k], n, [&](int c) { cell_items_[fill[size_t(c)]++] = k; });
}

// Overlapping coins add up (the paper's sum); where two strong ones both act fully, their
// weights can sum above 1 and pull a point past them. Overlapping disks share a cell. Only coins
// stronger than 1 minus the cell's strongest of their sign can form such a pair, so thousands of
// coincident weak coins cost one pass per cell, not a pass per pair. The first such pair's
// warning, or empty.
std::string CoinField::overlap_warning() const {
  for (size_t c = 0; c + 1 < cell_start_.size(); ++c) {
    double strongest[2] = {0, 0};  // of the negative, positive coins
    for (uint32_t a = cell_start_[c]; a < cell_start_[c + 1]; ++a) {
      const double m = sites_[cell_items_[a]].strength;
      strongest[m > 0] = std::max(strongest[m > 0], std::abs(m));
    }
    for (uint32_t a = cell_start_[c]; a < cell_start_[c + 1]; ++a) {
      const double m = sites_[cell_items_[a]].strength;
      if (!(std::abs(m) + strongest[m > 0] > 1)) continue;
      for (uint32_t b = a + 1; b < cell_start_[c + 1]; ++b) {
        const CoinSite &s = sites_[cell_items_[a]], &t = sites_[cell_items_[b]];
        if (length(s.uv - t.uv) < s.radius + t.radius &&
            std::abs(s.strength) + std::abs(t.strength) > 1 && (s.strength > 0) == (t.strength > 0))
          return fmt::format(
              "coin[{}] and coin[{}] overlap in the image and their strengths sum above 1: "
              "where both act fully, points are pulled past the coins",
              s.coin, t.coin);
      }
    }
  }
  return {};
}

template <class F>
void CoinField::for_cell(Vec2 uv, F&& f) const {
  const size_t c = size_t(cell_index(uv.y, grid_)) * grid_ + cell_index(uv.x, grid_);
  for (uint32_t k = cell_start_[c], e = cell_start_[c + 1]; k < e; ++k) f(cell_items_[k]);
}

bool CoinField::reaches(Vec2 uv) const {
  if (sites_.empty()) return false;
  bool hit = false;
  for_cell(uv, [&](uint32_t i) {
    const Disk& k = disks_[i];
    const double qu = uv.x - k.u, qv = uv.y - k.v;
    hit |= (qu * qu + qv * qv) * k.inv_r2 < 1;
  });
  return hit;
}

namespace {

// The sums of apply() over a batch's lanes, structure of arrays (see the formulas there).
struct CoinSums {
  static constexpr int N = kCameraBatch;
  double D[3][N], Du[3][N], Dv[3][N], C[3][N], Cu[3][N], Cv[3][N];
  double Wo[N], W[N], Wu[N], Wv[N], Sa[N];
  double moved[N], bent[N];  // masks: some coin moved the origin / bent the direction

  // Zeroes the lanes in use: all of them (4.4 KB) for a packet, element by element for a single
  // ray (zeroing loops of variable length become a library call each).
  void clear(int n) {
    if (n > 1) {
      *this = CoinSums{};
      return;
    }
    for (auto* a : {&D, &Du, &Dv, &C, &Cu, &Cv})
      for (auto& c : *a) c[0] = 0;
    for (double* a : {Wo, W, Wu, Wv, Sa, moved, bent}) a[0] = 0;
  }
};

// One site's contribution to every lane; lanes outside its radius add nothing (selects, with the
// arithmetic kept finite there so nothing traps).
struct SiteLanes {
  double u, v, inv_r2, inv_lc2, strength, stiffness;
  Vec3 pc;  // the coin in camera space
};

template <CoinFalloff kF, bool kOrg, bool kDir>
[[gnu::always_inline]] inline void add_site(const SiteLanes& site, const double* __restrict u,
                                            const double* __restrict v,
                                            const CameraRayBatch& __restrict r, int n,
                                            CoinSums* __restrict acc) {
  const SiteLanes c = site;
  const auto at = [](const double(&a)[3][kCameraBatch], int i) __attribute__((always_inline)) {
    return Vec3{a[0][i], a[1][i], a[2][i]};
  };
  const auto add =
      [](double(&a)[3][kCameraBatch], int i, const Vec3& x) __attribute__((always_inline)) {
    a[0][i] += x.x, a[1][i] += x.y, a[2][i] += x.z;
  };
  for (int i = 0; i < n; ++i) {
    const double qu = u[i] - c.u, qv = v[i] - c.v;
    const double x0 = (qu * qu + qv * qv) * c.inv_r2;
    const bool in = x0 < 1;
    const double x = in ? x0 : 0.0;
    const Vec3 p = at(r.org, i), pu = at(r.dorg_du, i), pv = at(r.dorg_dv, i);
    // w = m F(x) A(z): F = B_s(K(x)) with x = d^2 / R^2, A with z = l^2 / l_c^2.
    const KernelValue K = kernel(kF, x);
    const KernelValue B = stiffness(c.stiffness, K.k);
    const Vec3 e = c.pc - p;
    const double ee = dot(e, e), epu = dot(e, pu), epv = dot(e, pv), il = c.inv_lc2;
    const KernelValue A = distance(ee * il);
    // dx/du = 2 qu / R^2, dz/du = -2 (e . p_u) / l_c^2.
    const double mF = c.strength * B.k, mFx = c.strength * B.dk * K.dk * 2 * c.inv_r2;
    const double mFAz = mF * A.dk * -2 * il;
    const double w = in ? mF * A.k : 0.0;
    const double w_u = in ? mFx * qu * A.k + mFAz * epu : 0.0;
    const double w_v = in ? mFx * qv * A.k + mFAz * epv : 0.0;
    if (kOrg) {
      add(acc->D, i, e * w), add(acc->Du, i, e * w_u), add(acc->Dv, i, e * w_v);
      acc->Wo[i] += w;
      acc->moved[i] = in ? 1.0 : acc->moved[i];
    }
    if (kDir) {
      // A = 0 at the coin: it lets go of a point there.
      const bool bends = in & (ee > 0);
      const double il1 = 1 / std::sqrt(bends ? ee : 1.0);
      const double wd = bends ? w : 0.0, wd_u = bends ? w_u : 0.0, wd_v = bends ? w_v : 0.0;
      const double a = wd * il1;
      acc->W[i] += wd, acc->Wu[i] += wd_u, acc->Wv[i] += wd_v, acc->Sa[i] += a;
      add(acc->C, i, e * a);
      add(acc->Cu, i, e * ((wd_u + a * epu * il1) * il1));
      add(acc->Cv, i, e * ((wd_v + a * epv * il1) * il1));
      acc->bent[i] = bends ? 1.0 : acc->bent[i];
    }
  }
}

template <CoinFalloff kF>
[[gnu::always_inline]] inline void add_site_by_affects(const SiteLanes& site, CoinAffects affects,
                                                       const double* u, const double* v,
                                                       const CameraRayBatch& r, int n,
                                                       CoinSums* acc) {
  switch (affects) {
    case CoinAffects::Org:
      return add_site<kF, true, false>(site, u, v, r, n, acc);
    case CoinAffects::Dir:
      return add_site<kF, false, true>(site, u, v, r, n, acc);
    case CoinAffects::Both:
      return add_site<kF, true, true>(site, u, v, r, n, acc);
  }
}

ANAMORPH_KERNEL_BODY void add_site_lanes_body(const SiteLanes& site, CoinFalloff falloff,
                                              CoinAffects affects, const double* u, const double* v,
                                              const CameraRayBatch& r, int n, CoinSums* acc) {
  with_trip_count<kCameraBatch>(
      n, [&](auto m) __attribute__((always_inline)) {
        switch (falloff) {
          case CoinFalloff::Smooth:
            return add_site_by_affects<CoinFalloff::Smooth>(site, affects, u, v, r, m, acc);
          case CoinFalloff::Quadratic:
            return add_site_by_affects<CoinFalloff::Quadratic>(site, affects, u, v, r, m, acc);
          case CoinFalloff::Gaussian:
            return add_site_by_affects<CoinFalloff::Gaussian>(site, affects, u, v, r, m, acc);
        }
      });
}
constexpr simd::Kernel<add_site_lanes_body> add_site_lanes;

// The deformed rays from the sums; ok[i] = 0 where the bent direction vanishes (no ray).
[[gnu::always_inline]] inline void deform_kernel(const CoinSums& __restrict s, int n,
                                                 CameraRayBatch* __restrict r,
                                                 double* __restrict ok) {
  const auto at = [](const double(&a)[3][kCameraBatch], int i) __attribute__((always_inline)) {
    return Vec3{a[0][i], a[1][i], a[2][i]};
  };
  const auto put = [](double(&a)[3][kCameraBatch], int i, bool keep_old, const Vec3& x)
      __attribute__((always_inline)) {
    a[0][i] = keep_old ? a[0][i] : x.x, a[1][i] = keep_old ? a[1][i] : x.y;
    a[2][i] = keep_old ? a[2][i] : x.z;
  };
  for (int i = 0; i < n; ++i) {
    const Vec3 p = at(r->org, i), pu = at(r->dorg_du, i), pv = at(r->dorg_dv, i);
    const bool moved = s.moved[i] != 0, bent = s.bent[i] != 0;
    put(r->org, i, !moved, p + at(s.D, i));
    put(r->dorg_du, i, !moved, pu + (at(s.Du, i) - pu * s.Wo[i]));
    put(r->dorg_dv, i, !moved, pv + (at(s.Dv, i) - pv * s.Wo[i]));
    const Vec3 d0 = at(r->dir, i);
    const double W = s.W[i];
    const Vec3 d = d0 * (1 - W) + at(s.C, i);
    const Vec3 du = at(r->ddir_du, i) * (1 - W) - d0 * s.Wu[i] + (at(s.Cu, i) - pu * s.Sa[i]);
    const Vec3 dv = at(r->ddir_dv, i) * (1 - W) - d0 * s.Wv[i] + (at(s.Cv, i) - pv * s.Sa[i]);
    const double len = length(d);
    const bool fine = (len > 0) & (len * 0 == 0);  // bent exactly backwards: no ray
    ok[i] = (bent & !fine) ? 0.0 : 1.0;
    const double inv = 1 / (fine ? len : 1.0);
    const Vec3 nd = d * inv;
    put(r->dir, i, !bent, nd);
    put(r->ddir_du, i, !bent, (du - nd * dot(nd, du)) * inv);
    put(r->ddir_dv, i, !bent, (dv - nd * dot(nd, dv)) * inv);
  }
}

ANAMORPH_KERNEL_BODY void deform_lanes_body(const CoinSums& s, int n, CameraRayBatch* r,
                                            double* ok) {
  with_trip_count<kCameraBatch>(
      n, [&](auto m) __attribute__((always_inline)) { deform_kernel(s, m, r, ok); });
}
constexpr simd::Kernel<deform_lanes_body> deform_lanes;

}  // namespace

bool CoinField::may_reach(const double* u, const double* v, int n) const {
  if (sites_.empty() || n == 0) return false;
  double u0 = u[0], u1 = u[0], v0 = v[0], v1 = v[0];
  for (int i = 1; i < n; ++i) {
    u0 = std::min(u0, u[i]), u1 = std::max(u1, u[i]);
    v0 = std::min(v0, v[i]), v1 = std::max(v1, v[i]);
  }
  // Every site whose disk touches the box is listed in a cell the box overlaps.
  const int i0 = cell_index(u0, grid_), i1 = cell_index(u1, grid_);
  const int j0 = cell_index(v0, grid_), j1 = cell_index(v1, grid_);
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i) {
      const size_t c = size_t(j) * grid_ + i;
      for (uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
        const Disk& d = disks_[cell_items_[k]];
        const double qu = std::clamp(d.u, u0, u1) - d.u, qv = std::clamp(d.v, v0, v1) - d.v;
        if ((qu * qu + qv * qv) * d.inv_r2 < 1) return true;
      }
    }
  return false;
}

bool CoinField::apply(Vec2 uv, CameraRay* r) const {
  if (sites_.empty()) return true;
  CameraRayBatch b;
  b.set(0, *r);
  bool reached;
  apply_batch(&uv.x, &uv.y, 1, &b, &reached);
  if (!reached) return true;  // untouched, bit for bit
  if (!b.valid[0]) return false;
  *r = b.ray(0);
  return true;
}

void CoinField::apply_batch(const double* u, const double* v, int n, CameraRayBatch* rays,
                            bool* reached) const {
  for (int i = 0; i < n; ++i) reached[i] = false;
  if (sites_.empty()) return;
  // The sites that reach some lane, in increasing order, at most kMaxSites per pass: each pass
  // takes the smallest indices above the previous pass's last one. Every lane thus adds its coins
  // in one global order (the same bits whatever its neighbours are), with no allocation and no
  // limit on how many coins reach a sample.
  constexpr int kMaxSites = 64;
  uint32_t cand[kMaxSites];
  CoinSums s;
  bool any = false;
  int64_t after = -1;
  for (;;) {
    int m = 0;
    bool more = false;
    for (int i = 0; i < n; ++i)
      for_cell({u[i], v[i]}, [&](uint32_t k) {
        const Disk& d = disks_[k];
        const double qu = u[i] - d.u, qv = v[i] - d.v;
        if (!((qu * qu + qv * qv) * d.inv_r2 < 1)) return;
        reached[i] = true;
        if (int64_t(k) <= after) return;
        uint32_t* at = std::lower_bound(cand, cand + m, k);
        if (at != cand + m && *at == k) return;
        if (m == kMaxSites) {
          more = true;  // the largest one waits for the next pass
          if (at == cand + m) return;
          --m;
        }
        std::copy_backward(at, cand + m, cand + m + 1);
        *at = k;
        ++m;
      });
    if (m == 0) break;
    if (!any) s.clear(n), any = true;
    for (int j = 0; j < m; ++j) {
      const uint32_t k = cand[j];
      const CoinSite& c = sites_[k];
      const SiteLanes lane{disks_[k].u, disks_[k].v, disks_[k].inv_r2, inv_lc2_[k],
                           c.strength,  c.stiffness, c.p_camera};
      add_site_lanes(lane, c.falloff, c.affects, u, v, *rays, n, &s);
    }
    if (!more) break;
    after = cand[m - 1];
  }
  if (!any) return;
  double ok[kCameraBatch];
  deform_lanes(s, n, rays, ok);
  for (int i = 0; i < n; ++i) rays->valid[i] = rays->valid[i] & (ok[i] != 0);
}

double CoinField::overlay(Vec2 uv, Vec2 pixel) const {
  if (sites_.empty()) return 0;
  // Markers reach up to ~1.3 pixels outside a radius: look at the cells around uv too.
  const double mu = 2 * pixel.x, mv = 2 * pixel.y;
  const int i0 = cell_index(uv.x - mu, grid_), i1 = cell_index(uv.x + mu, grid_);
  const int j0 = cell_index(uv.y - mv, grid_), j1 = cell_index(uv.y + mv, grid_);
  double cov = 0;
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i) {
      const size_t c = size_t(j) * grid_ + i;
      for (uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
        const CoinSite& s = sites_[cell_items_[k]];
        const Vec2 q = uv - s.uv;
        const Vec2 qp{q.x / pixel.x, q.y / pixel.y};  // in pixels
        cov = std::max(cov, std::clamp(3.5 - length(qp), 0.0, 1.0));
        const double r = length(q);
        if (r > 0) {
          // Distance to the circle |q| = R in pixels, to first order.
          const double dist =
              std::abs(r - s.radius) * r / length(Vec2{q.x * pixel.x, q.y * pixel.y});
          cov = std::max(cov, std::clamp(1.25 - dist, 0.0, 1.0));
        }
      }
    }
  return cov;
}

std::span<const CoinSite> coin_sites(const VirtualCamera& cam) { return cam.coins().sites(); }

double coin_overlay(const VirtualCamera& cam, Vec2 uv, Vec2 pixel) {
  return cam.coins().overlay(uv, pixel);
}

}  // namespace anamorph
