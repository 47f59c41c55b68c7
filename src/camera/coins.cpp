// Centers of interest: the weight function, the coins' parameter table, and CoinField, which
// finds each coin's (uc, vc) and deforms samples using only the coins whose radius reaches them
// (a uniform grid over (u, v)).
#include "camera/coins.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "camera/camera.h"
#include "camera/virtual_camera.h"

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
  const double lo = coin_min_strength(c.stiffness, c.falloff);
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

bool affects_org(CoinAffects a) { return (uint8_t(a) & uint8_t(CoinAffects::Org)) != 0; }
bool affects_dir(CoinAffects a) { return (uint8_t(a) & uint8_t(CoinAffects::Dir)) != 0; }

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
    const Coin& c = coins[i];
    // Dropped, not weighted by zero: a strength-0 coin leaves every ray bit-identical.
    if (c.strength == 0) continue;
    const Vec3 pc = camera_from_world.point(c.position);
    const std::vector<Vec2> uvs = project_world(c.position);
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
                        i, uv.x, uv.y));
        continue;
      }
      CoinSite site;
      site.coin = int(i);
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
    if (seen == 0)
      warn(
          fmt::format("coin[{}]: the camera does not see position [{}, {}, {}], so the coin has "
                      "no effect",
                      i, c.position.x, c.position.y, c.position.z));
  }
  if (sites_.empty()) return;

  for (const CoinSite& s : sites_) {
    disks_.push_back({s.uv.x, s.uv.y, 1 / (s.radius * s.radius)});
    inv_lc2_.push_back(1 / (s.lc * s.lc));
  }

  // Cells about as large as the median radius: a disk then covers a handful of cells and a cell
  // holds only the coins that can reach it.
  std::vector<double> radii;
  for (const CoinSite& s : sites_) radii.push_back(s.radius);
  std::nth_element(radii.begin(), radii.begin() + radii.size() / 2, radii.end());
  grid_ = std::clamp(int(std::ceil(1 / radii[radii.size() / 2])), 1, 512);
  const int n = grid_;
  const auto cells_of = [&](const CoinSite& s, auto&& f) {
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
  };
  cell_start_.assign(size_t(n) * n + 1, 0);
  for (const CoinSite& s : sites_) cells_of(s, [&](int c) { ++cell_start_[size_t(c) + 1]; });
  for (size_t c = 1; c < cell_start_.size(); ++c) cell_start_[c] += cell_start_[c - 1];
  cell_items_.resize(cell_start_.back());
  std::vector<uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (uint32_t k = 0; k < sites_.size(); ++k)
    cells_of(sites_[k], [&](int c) { cell_items_[fill[size_t(c)]++] = k; });

  // Overlapping coins add up (the paper's sum); where two strong ones both act fully, their
  // weights can sum above 1 and pull a point past them. Overlapping disks share a cell.
  for (size_t c = 0; c + 1 < cell_start_.size(); ++c) {
    for (uint32_t a = cell_start_[c]; a < cell_start_[c + 1]; ++a)
      for (uint32_t b = a + 1; b < cell_start_[c + 1]; ++b) {
        const CoinSite &s = sites_[cell_items_[a]], &t = sites_[cell_items_[b]];
        if (length(s.uv - t.uv) < s.radius + t.radius &&
            std::abs(s.strength) + std::abs(t.strength) > 1 &&
            (s.strength > 0) == (t.strength > 0)) {
          warn(
              fmt::format("coin[{}] and coin[{}] overlap in the image and their strengths sum "
                          "above 1: where both act fully, points are pulled past the coins",
                          s.coin, t.coin));
          return;
        }
      }
  }
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

bool CoinField::apply(Vec2 uv, CameraRay* r) const {
  if (sites_.empty()) return true;
  const Vec3 p = r->org, pu = r->dorg_du, pv = r->dorg_dv;
  bool moved = false, bent = false;
  // Origin: D = sum w_i e_i with e_i = p_c,i - p (de_i/du = -p_u), so
  //   dD/du = sum w_u,i e_i - p_u sum w_i.
  // Direction: sum w_i (c_i - d) = C - W d with c_i = e_i / l_i, W = sum w_i, C = sum w_i c_i;
  //   d(w c)/du = (w_u + a (c . p_u)) c - a p_u with a = w / l, so
  //   dC/du = sum (w_u,i + a_i (c_i . p_u)) c_i - p_u sum a_i.
  // Sums that multiply p_u or p_v are applied once at the end.
  Vec3 D, Du, Dv, C, Cu, Cv;
  double Wo = 0, W = 0, Wu = 0, Wv = 0, Sa = 0;
  for_cell(uv, [&](uint32_t i) {
    const Disk& k = disks_[i];
    const double qu = uv.x - k.u, qv = uv.y - k.v;
    const double x = (qu * qu + qv * qv) * k.inv_r2;
    if (!(x < 1)) return;
    const CoinSite& c = sites_[i];
    // w = m F(x) A(z): F = B_s(K(x)) with x = d^2 / R^2, A with z = l^2 / l_c^2.
    const KernelValue K = kernel(c.falloff, x);
    const KernelValue B = stiffness(c.stiffness, K.k);
    const Vec3 e = c.p_camera - p;
    const double ee = dot(e, e), epu = dot(e, pu), epv = dot(e, pv), il = inv_lc2_[i];
    const KernelValue A = distance(ee * il);
    // dx/du = 2 qu / R^2, dz/du = -2 (e . p_u) / l_c^2.
    const double mF = c.strength * B.k, mFx = c.strength * B.dk * K.dk * 2 * k.inv_r2;
    const double mFAz = mF * A.dk * -2 * il;
    const double w = mF * A.k;
    const double w_u = mFx * qu * A.k + mFAz * epu;
    const double w_v = mFx * qv * A.k + mFAz * epv;
    if (affects_org(c.affects)) {
      D += e * w;
      Du += e * w_u;
      Dv += e * w_v;
      Wo += w;
      moved = true;
    }
    if (affects_dir(c.affects)) {
      if (!(ee > 0)) return;  // A = 0 there: the coin lets go of a point at the coin
      const double il1 = 1 / std::sqrt(ee), a = w * il1;
      W += w;
      Wu += w_u;
      Wv += w_v;
      Sa += a;
      C += e * a;
      Cu += e * ((w_u + a * epu * il1) * il1);
      Cv += e * ((w_v + a * epv * il1) * il1);
      bent = true;
    }
  });
  if (moved) {
    r->org = p + D;
    r->dorg_du = pu + (Du - pu * Wo);
    r->dorg_dv = pv + (Dv - pv * Wo);
  }
  if (bent) {
    const Vec3 d0 = r->dir;
    const Vec3 d = d0 * (1 - W) + C;
    const Vec3 du = r->ddir_du * (1 - W) - d0 * Wu + (Cu - pu * Sa);
    const Vec3 dv = r->ddir_dv * (1 - W) - d0 * Wv + (Cv - pv * Sa);
    const double len = length(d);
    if (!(len > 0) || !std::isfinite(len)) return false;  // bent exactly backwards: no ray
    const double inv = 1 / len;
    r->dir = d * inv;
    r->ddir_du = (du - r->dir * dot(r->dir, du)) * inv;
    r->ddir_dv = (dv - r->dir * dot(r->dir, dv)) * inv;
  }
  return true;
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

std::span<const CoinSite> coin_sites(const Camera& cam) {
  if (const auto* v = dynamic_cast<const VirtualCamera*>(&cam)) return v->coins().sites();
  return {};
}

double coin_overlay(const Camera& cam, Vec2 uv, Vec2 pixel) {
  if (const auto* v = dynamic_cast<const VirtualCamera*>(&cam))
    return v->coins().overlay(uv, pixel);
  return 0;
}

}  // namespace anamorph
