// Centers of interest: the weight function's properties, the ray field they produce (identity at
// strength 0 and beyond the radius, continuity, magnification, the paper's sum, differentials),
// the (uc, vc) projection and the inverse map with coins, the [[camera.coin]] reader and the
// `--aov coins` overlay.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "camera/coins.h"
#include "camera/presets.h"
#include "camera/virtual_camera.h"
#include "math/rng.h"
#include "preset_test_util.h"
#include "render/render_util.h"
#include "scene/scene_loader.h"
#include "scene/toml_reader.h"
#include "test_util.h"

namespace anamorph {
namespace {

using test::str;

constexpr CoinFalloff kFalloffs[] = {CoinFalloff::Smooth, CoinFalloff::Quadratic,
                                     CoinFalloff::Gaussian};
const char* name(CoinFalloff f) {
  return f == CoinFalloff::Smooth      ? "smooth"
         : f == CoinFalloff::Quadratic ? "quadratic"
                                       : "gaussian";
}

// ---- the weight ---------------------------------------------------------------------------------

TEST(CoinWeight, ExactlyZeroBeyondTheRadiusAndPositiveInside) {
  for (CoinFalloff f : kFalloffs)
    for (double s : {0.05, 1.0, 20.0})
      for (double l : {0.1, 1.0, 3.0}) {
        const double R = 0.3;
        for (double d : {R, R * (1 + 1e-15), 0.31, 0.5, 2.0, 1e300})
          EXPECT_EQ(coin_weight(0.7, l, d, s, R, 1.0, f), 0.0)
              << name(f) << " s=" << s << " l=" << l << " d=" << d;
        EXPECT_GT(coin_weight(0.7, l, R * 0.999, s, R, 1.0, f), 0.0) << name(f) << " s=" << s;
      }
}

TEST(CoinWeight, BoundedByStrengthAndEqualToItAtTheCenter) {
  // 0 <= w <= m <= 1: the point moves at most all the way to its coin, never past it.
  for (CoinFalloff f : kFalloffs)
    for (double m : {0.25, 0.9, 1.0})
      for (double s : {0.05, 0.5, 1.0, 4.0, 50.0}) {
        EXPECT_NEAR(coin_weight(m, 2.0, 0.0, s, 0.2, 2.0, f), m, 1e-15) << name(f) << " s=" << s;
        for (int i = 0; i <= 200; ++i)
          for (double l : {0.0, 1e-3, 0.5, 1.0, 1.7, 10.0, 1e4}) {
            const double d = 0.25 * i / 200;
            const double w = coin_weight(m, l, d, s, 0.2, 1.0, f);
            ASSERT_GE(w, 0.0) << name(f) << " m=" << m << " s=" << s << " l=" << l << " d=" << d;
            ASSERT_LE(w, m) << name(f) << " m=" << m << " s=" << s << " l=" << l << " d=" << d;
          }
      }
}

TEST(CoinWeight, DeclinesStrictlyWithParametricDistance) {
  for (CoinFalloff f : kFalloffs)
    for (double s : {0.05, 1.0, 20.0})
      for (double l : {0.3, 1.0, 4.0}) {
        double prev = coin_weight(0.8, l, 0.0, s, 0.5, 1.0, f);
        for (int i = 1; i <= 1000; ++i) {
          const double d = 0.5 * i / 1000;
          const double w = coin_weight(0.8, l, d, s, 0.5, 1.0, f);
          ASSERT_LT(w, prev) << name(f) << " s=" << s << " l=" << l << " d=" << d;
          prev = w;
        }
      }
}

// Largest jump of the numerical derivative dw/dd between neighbouring samples of [0, 1.5 R] at
// step h: it shrinks like h for a C1 function and stays put for a kink.
double largest_slope_jump(CoinFalloff f, double s, double h) {
  const double R = 0.4;
  const auto w = [&](double d) { return coin_weight(0.9, 1.3, std::abs(d), s, R, 1.0, f); };
  double worst = 0, prev = (w(h) - w(-h)) / (2 * h);
  for (double d = h; d <= 1.5 * R; d += h) {
    const double slope = (w(d + h) - w(d - h)) / (2 * h);
    worst = std::max(worst, std::abs(slope - prev));
    prev = slope;
  }
  return worst;
}

TEST(CoinWeight, IsC1AcrossTheCenterAndTheRadius) {
  for (CoinFalloff f : kFalloffs)
    for (double s : {0.2, 1.0, 5.0}) {
      const double j1 = largest_slope_jump(f, s, 1e-3), j2 = largest_slope_jump(f, s, 5e-4),
                   j3 = largest_slope_jump(f, s, 2.5e-4);
      EXPECT_LT(j2, 0.6 * j1) << name(f) << " s=" << s << ": jumps " << j1 << " " << j2;
      EXPECT_LT(j3, 0.6 * j2) << name(f) << " s=" << s << ": jumps " << j2 << " " << j3;
      // One-sided slopes at the radius: the inside one tends to the outside one, 0.
      const double R = 0.4, h = 1e-7;
      const double inside =
          (coin_weight(0.9, 1.3, R, s, R, 1.0, f) - coin_weight(0.9, 1.3, R - h, s, R, 1.0, f)) / h;
      EXPECT_NEAR(inside, 0.0, 1e-4) << name(f) << " s=" << s;
      // At the center w is flat in every direction (a radial function is C1 there only then).
      const double center =
          (coin_weight(0.9, 1.3, h, s, R, 1.0, f) - coin_weight(0.9, 1.3, 0, s, R, 1.0, f)) / h;
      EXPECT_NEAR(center, 0.0, 1e-4) << name(f) << " s=" << s;
    }
  // The kernels' analytic derivatives agree with their values.
  for (CoinFalloff f : kFalloffs)
    for (double x : {0.0, 0.1, 0.5, 0.9, 0.999}) {
      const double h = 1e-6;
      const KernelValue k = coin_kernel(f, x), kp = coin_kernel(f, x + h);
      EXPECT_NEAR((kp.k - k.k) / h, k.dk, 1e-4) << name(f) << " x=" << x;
      EXPECT_NEAR((kp.dk - k.dk) / h, k.d2k, 1e-3) << name(f) << " x=" << x;
    }
}

TEST(CoinWeight, LowStiffnessConcentratesTheDeformationNearTheCenter) {
  // Radius within which w exceeds half its central value, for increasing stiffness.
  for (CoinFalloff f : kFalloffs) {
    double prev = 0;
    for (double s : {0.02, 0.1, 0.5, 1.0, 3.0, 20.0}) {
      double half = 0;
      for (int i = 0; i <= 10000; ++i)
        if (coin_weight(1, 1, i / 10000.0, s, 1, 1, f) > 0.5) half = i / 10000.0;
      EXPECT_GT(half, prev) << name(f) << " s=" << s;
      prev = half;
    }
    EXPECT_LT(
        [&] {
          double h = 0;
          for (int i = 0; i <= 1000; ++i)
            if (coin_weight(1, 1, i / 1000.0, 0.02, 1, 1, f) > 0.5) h = i / 1000.0;
          return h;
        }(),
        0.2)
        << name(f) << ": a flexible surface deforms significantly only near (uc, vc)";
  }
}

TEST(CoinWeight, DistanceTermPeaksAtTheCoinsDistanceAndFallsLikeInverseSquare) {
  // A(l) = 2 (l/lc)^2 / (1 + (l/lc)^4): 1 at l = lc, below elsewhere, 0 at the coin, ~2 (lc/l)^2.
  EXPECT_DOUBLE_EQ(coin_weight(1, 2.5, 0, 1, 1, 2.5), 1.0);
  for (double l : {0.0, 0.5, 2.0, 2.4, 2.6, 4.0, 100.0})
    EXPECT_LT(coin_weight(1, l, 0, 1, 1, 2.5), 1.0) << "l=" << l;
  EXPECT_EQ(coin_weight(1, 0, 0, 1, 1, 2.5), 0.0);
  EXPECT_NEAR(coin_weight(1, 2500, 0, 1, 1, 2.5) * 1e6, 2.0, 1e-5);
  // Scale free: only l / lc matters.
  EXPECT_DOUBLE_EQ(coin_weight(0.6, 3, 0.1, 2, 0.3, 2), coin_weight(0.6, 300, 0.1, 2, 0.3, 200));
  for (double z : {0.01, 0.5, 1.0, 2.0, 7.0}) {
    const double h = 1e-6;
    const KernelValue a = coin_distance(z), ap = coin_distance(z + h);
    EXPECT_NEAR((ap.k - a.k) / h, a.dk, 1e-5) << "z=" << z;
    EXPECT_NEAR((ap.dk - a.dk) / h, a.d2k, 1e-4) << "z=" << z;
    const KernelValue b = coin_stiffness(3.0, z / 8), bp = coin_stiffness(3.0, z / 8 + h);
    EXPECT_NEAR((bp.k - b.k) / h, b.dk, 1e-5) << "y=" << z / 8;
    EXPECT_NEAR((bp.dk - b.dk) / h, b.d2k, 1e-4) << "y=" << z / 8;
  }
}

// Whether the radial map r -> (1 - w(r)) r of a pinhole image is increasing (no fold-over).
bool radial_map_monotone(double m, double s, CoinFalloff f) {
  double prev = -1;
  for (int i = 0; i <= 20000; ++i) {
    const double r = 1.2 * i / 20000;
    const double y = (1 - coin_weight(m, 1, r, s, 1, 1, f)) * r;
    if (!(y > prev)) return false;
    prev = y;
  }
  return true;
}

TEST(CoinWeight, NoFoldOverForAttractionAndWithinTheRepulsionLimit) {
  for (CoinFalloff f : kFalloffs)
    for (double s : {0.05, 0.3, 1.0, 5.0}) {
      for (double m : {0.3, 0.9, 0.999})
        EXPECT_TRUE(radial_map_monotone(m, s, f)) << name(f) << " s=" << s << " m=" << m;
      const double lo = coin_min_strength(s, f);
      EXPECT_GE(lo, -1.0);
      EXPECT_LT(lo, 0.0);
      EXPECT_TRUE(radial_map_monotone(lo, s, f)) << name(f) << " s=" << s << " limit " << lo;
      // The limit is tight: 3% beyond it the image folds.
      if (lo > -0.97) {
        EXPECT_FALSE(radial_map_monotone(lo * 1.03, s, f)) << name(f) << " s=" << s << " " << lo;
      }
    }
  EXPECT_THROW(make_coin("position = [0, 0, -1]\nstrength = -0.9\nstiffness = 10"), ParamError);
  EXPECT_NO_THROW(make_coin("position = [0, 0, -1]\nstrength = -0.1"));
}

// The declaration says strength lies in [-1, 1]: the reader takes its upper end, 1 (the image
// surface moves all the way to the coin at (uc, vc)), and refuses just beyond it; a scene with it
// builds a camera whose rays around the coin are finite.
TEST(CoinWeight, DeclaredStrengthOfOneIsAccepted) {
  const ParamSpec* spec = nullptr;
  for (const ParamSpec& p : coin_params())
    if (p.name == "strength") spec = &p;
  ASSERT_NE(spec, nullptr);
  EXPECT_EQ(spec->max, 1.0);
  EXPECT_FALSE(spec->max_exclusive);
  for (const char* affects : {"org", "dir", "both"}) {
    const std::string c = fmt::format("position = [0, 0, -1]\naffects = \"{}\"\n", affects);
    EXPECT_NO_THROW(make_coin(c + "strength = 1")) << affects;
    EXPECT_THROW(make_coin(c + "strength = 1.000001"), ParamError) << affects;
    const Scene s = load_scene_from_string("[[camera.coin]]\n" + c + "strength = 1\n", "one.toml");
    for (double u : {0.4, 0.45, 0.49, 0.5, 0.51, 0.55, 0.6}) {
      CameraSample cs;
      cs.uv = {u, 0.5};
      const std::optional<CameraRay> r = s.camera->generate(cs);
      ASSERT_TRUE(r) << affects << " u " << u;
      EXPECT_TRUE(std::isfinite(r->dir.x) && std::isfinite(r->org.x) &&
                  std::isfinite(r->ddir_du.x) && std::isfinite(r->dorg_du.x))
          << affects << " u " << u << ": dir " << r->dir.x << " org " << r->org.x;
    }
  }
}

// ---- cameras with coins
// --------------------------------------------------------------------------

using Rays = std::vector<std::optional<CameraRay>>;

Rays ray_grid(const Camera& cam, int w, int h) {
  Rays out;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) out.push_back(test::ray(cam, {(x + 0.5) / w, (y + 0.5) / h}));
  return out;
}

bool bit_identical(const std::optional<CameraRay>& a, const std::optional<CameraRay>& b) {
  if (bool(a) != bool(b)) return false;
  return !a || std::memcmp(&*a, &*b, sizeof(CameraRay)) == 0;
}

struct CamCase {
  std::string label;
  std::function<VirtualCameraParts()> parts;
  Vec3 coin;  // a point the camera sees well
};

// Cameras with a rig that is not the identity; the coin is in front of each.
std::vector<CamCase> setups() {
  const std::string rig = "look_from = [1, 2, 3]\nlook_at = [1, 2, -7]\nup = [0, 1, 0]\n";
  const Transform look = Transform::look_at({1, 2, 3}, {1, 2, -7}, {0, 1, 0});
  return {
      {"perspective",
       [=] {
         return make_preset("perspective", rig + "fov = 60", {400, 300});
       },
       {1.4, 2.3, -2}},
      {"fisheye",
       [=] {
         return make_preset("fisheye", rig + "fov = 180", {300, 300});
       },
       {2.5, 1.5, 0}},
      {"orthographic",
       [=] {
         return make_preset("orthographic", rig + "view_width = 4", {400, 300});
       },
       {1.5, 2.4, -1}},
      {"equirectangular",
       [=] {
         return make_preset("equirectangular", rig, {400, 200});
       },
       {-1, 2.5, 1}},
      {"plane + normal",
       [=] {
         VirtualCameraParts p;
         p.org = make_org("plane", "edge_u = [4, 0, 0]\nedge_v = [0, -3, 0]");
         p.dir = make_dir("normal");
         p.world_from_camera = look;
         p.description = "plane + normal";
         return p;
       },
       {1.6, 1.7, -3}},
      {"sphere + normal",
       [=] {
         VirtualCameraParts p;
         p.org = make_org("sphere", "radius = 0.5\nu_range = [-60, 60]\nv_range = [50, -50]");
         p.dir = make_dir("normal");
         p.world_from_camera = look;
         p.description = "sphere + normal";
         return p;
       },
       {2, 2.5, -3}},
  };
}

VirtualCamera with_coins(const CamCase& s, std::vector<Coin> coins, DepthOfField dof = {}) {
  VirtualCameraParts p = s.parts();
  p.coins = std::move(coins);
  return VirtualCamera(std::move(p), dof);
}

Coin coin_at(Vec3 p, double m, CoinAffects a = CoinAffects::Both, double radius = 0.2,
             double stiffness = 1, CoinFalloff f = CoinFalloff::Smooth) {
  Coin c;
  c.position = p;
  c.strength = m;
  c.affects = a;
  c.radius = radius;
  c.stiffness = stiffness;
  c.falloff = f;
  return c;
}

constexpr CoinAffects kAffects[] = {CoinAffects::Org, CoinAffects::Dir, CoinAffects::Both};
const char* name(CoinAffects a) {
  return a == CoinAffects::Org ? "org" : a == CoinAffects::Dir ? "dir" : "both";
}

TEST(CoinCamera, StrengthZeroIsBitIdenticalToNoCoin) {
  for (const CamCase& s : setups()) {
    const VirtualCamera plain(s.parts());
    const VirtualCamera coined =
        with_coins(s, {coin_at(s.coin, 0.0), coin_at(s.coin, 0.0, CoinAffects::Org)});
    EXPECT_TRUE(coined.coins().empty()) << s.label;
    EXPECT_EQ(plain.has_linear_fast_path(), coined.has_linear_fast_path()) << s.label;
    const Rays a = ray_grid(plain, 64, 48), b = ray_grid(coined, 64, 48);
    for (size_t i = 0; i < a.size(); ++i)
      ASSERT_TRUE(bit_identical(a[i], b[i])) << s.label << " pixel " << i;
  }
}

TEST(CoinCamera, BeyondTheRadiusRaysAreBitIdenticalAndInsideTheyChange) {
  for (const CamCase& s : setups())
    for (CoinAffects a : kAffects) {
      const VirtualCamera plain(s.parts());
      const VirtualCamera coined = with_coins(s, {coin_at(s.coin, 0.6, a, 0.2)});
      ASSERT_EQ(coined.coins().sites().size(), 1u) << s.label << ": the coin must be seen once";
      const CoinSite& site = coined.coins().sites()[0];
      int outside = 0, inside_changed = 0, inside = 0;
      constexpr int W = 80, H = 60;
      for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
          const Vec2 uv{(x + 0.5) / W, (y + 0.5) / H};
          const auto r0 = test::ray(plain, uv), r1 = test::ray(coined, uv);
          const double d = length(uv - site.uv);
          if (d >= site.radius) {
            ++outside;
            ASSERT_TRUE(bit_identical(r0, r1))
                << s.label << " " << name(a) << " uv " << str(uv) << " d " << d;
          } else if (d > 0.02 && d < 0.5 * site.radius && r0 && r1) {
            ++inside;
            inside_changed += !bit_identical(r0, r1) && (length(r0->dir - r1->dir) > 1e-6 ||
                                                         length(r0->org - r1->org) > 1e-6);
          }
        }
      EXPECT_GT(outside, 0) << s.label;
      EXPECT_GT(inside, 0) << s.label;
      EXPECT_EQ(inside_changed, inside) << s.label << " " << name(a);
    }
}

TEST(CoinCamera, DepthOfFieldStillBitIdenticalBeyondTheRadius) {
  const CamCase s = setups()[0];
  DepthOfField dof{0.05, 4};
  const VirtualCamera plain(s.parts(), dof);
  const VirtualCamera coined = with_coins(s, {coin_at(s.coin, 0.5)}, dof);
  const CoinSite& site = coined.coins().sites()[0];
  Rng rng(7, 1);
  for (int i = 0; i < 2000; ++i) {
    CameraSample cs;
    cs.uv = {rng.uniform(), rng.uniform()};
    cs.lens = {rng.uniform(), rng.uniform()};
    if (length(cs.uv - site.uv) < site.radius) continue;
    ASSERT_TRUE(bit_identical(plain.generate(cs), coined.generate(cs))) << str(cs.uv);
  }
}

// Largest difference between the rays of neighbouring pixels (directions, and origins relative
// to the image surface's size) on an n x n grid.
double largest_neighbour_step(const Camera& cam, int n) {
  const Rays r = ray_grid(cam, n, n);
  double worst = 0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const auto& a = r[size_t(y) * n + x];
      for (const auto& b :
           {x + 1 < n ? r[size_t(y) * n + x + 1] : a, y + 1 < n ? r[size_t(y + 1) * n + x] : a})
        if (a && b) worst = std::max(worst, length(a->dir - b->dir) + length(a->org - b->org));
    }
  return worst;
}

TEST(CoinCamera, RayFieldIsContinuous) {
  // Strong, sharp coins: steps between neighbouring pixels must shrink like 1 / resolution.
  for (const CamCase& s : {setups()[0], setups()[4]})
    for (CoinAffects a : kAffects)
      for (CoinFalloff f : kFalloffs) {
        const VirtualCamera cam = with_coins(s, {coin_at(s.coin, 0.9, a, 0.3, 0.2, f)});
        double prev = largest_neighbour_step(cam, 32);
        for (int n = 64; n <= (test::kSanitized ? 256 : 512); n *= 2) {  // (512: 3/4 of the work)
          const double step = largest_neighbour_step(cam, n);
          EXPECT_LT(step, 0.65 * prev) << s.label << " " << name(a) << " " << name(f) << " n=" << n;
          prev = step;
        }
      }
}

// Pixels (of an n x n grid) whose ray passes within rho of p, in front of the origin.
int pixels_seeing(const Camera& cam, Vec3 p, double rho, int n) {
  int count = 0;
  for (const auto& r : ray_grid(cam, n, n)) {
    if (!r) continue;
    const Vec3 op = p - r->org;
    const double t = dot(op, r->dir);
    count += t > 0 && length(op - r->dir * t) < rho;
  }
  return count;
}

TEST(CoinCamera, StrongerCoinsMagnifyTheObjectAtTheCoin) {
  // Counted analytically: pixels whose ray passes within 0.1 of the coin position.
  for (const CamCase& s : setups())
    for (CoinAffects a : kAffects) {
      int prev = -1;
      for (double m : {0.0, 0.2, 0.4, 0.6, 0.8}) {
        const VirtualCamera cam = with_coins(s, {coin_at(s.coin, m, a, 0.25)});
        const int count = pixels_seeing(cam, s.coin, 0.1, 200);
        EXPECT_GT(count, prev) << s.label << " " << name(a) << " m=" << m;
        prev = count;
      }
    }
}

TEST(CoinCamera, RepellingCoinsShrinkTheObjectAtTheCoin) {
  for (const CamCase& s : setups())
    for (CoinAffects a : kAffects) {
      int prev = 1 << 30;
      for (double m : {0.0, -0.3, -0.6}) {
        const VirtualCamera cam = with_coins(s, {coin_at(s.coin, m, a, 0.25)});
        const int count = pixels_seeing(cam, s.coin, 0.1, 200);
        EXPECT_LT(count, prev) << s.label << " " << name(a) << " m=" << m;
        prev = count;
      }
    }
}

TEST(CoinCamera, ProjectFindsPointsUnderSmallStrongCoins) {
  // Coins smaller than the numeric inverse's seed grid (1/48), zooming up to 20x.
  const CamCase s = setups()[0];
  for (double m : {0.5, 0.95}) {
    const VirtualCamera cam = with_coins(s, {coin_at(s.coin, m, CoinAffects::Org, 0.015)});
    const Vec2 c = cam.coins().sites()[0].uv;
    for (Vec2 off : {Vec2{0.002, 0.001}, Vec2{-0.006, 0.004}, Vec2{0.01, -0.008}}) {
      const auto r = test::ray(cam, c + off);
      ASSERT_TRUE(r);
      const auto back = cam.project(r->org + r->dir * 4.0);
      bool found = false;
      for (const Vec2& q : back) found |= length(q - (c + off)) < 1e-6;
      EXPECT_TRUE(found) << "m=" << m << " uv " << str(c + off) << " projects to "
                         << test::str(back);
    }
  }
}

TEST(CoinCamera, WarnsWhenOverlappingCoinsCanPullPastThem) {
  const CamCase s = setups()[0];
  const Vec3 near = s.coin + Vec3{0.15, 0, 0};
  const VirtualCamera strong = with_coins(s, {coin_at(s.coin, 0.6), coin_at(near, 0.6)});
  ASSERT_EQ(strong.coin_warnings().size(), 1u);
  EXPECT_NE(strong.coin_warnings()[0].find("coin[0] and coin[1]"), std::string::npos)
      << strong.coin_warnings()[0];
  EXPECT_TRUE(with_coins(s, {coin_at(s.coin, 0.4), coin_at(near, 0.4)}).coin_warnings().empty());
  EXPECT_TRUE(with_coins(s, {coin_at(s.coin, 0.6, CoinAffects::Both, 0.05),
                             coin_at(s.coin + Vec3{2, 0, 0}, 0.6, CoinAffects::Both, 0.05)})
                  .coin_warnings()
                  .empty());
}

TEST(CoinCamera, ZoomAtTheCenterIsOneOverOneMinusStrength) {
  // A pinhole: attracting the origins or bending the directions by w scales angles at (uc, vc)
  // by (1 - w); both together by (1 - w)^2. Areas scale by the square.
  const CamCase s = setups()[0];
  const VirtualCamera plain(s.parts());
  const double rho = 0.05;
  const int n = 600;
  const double base = pixels_seeing(plain, s.coin, rho, n);
  ASSERT_GT(base, 30);
  for (CoinAffects a : kAffects) {
    const double m = 0.5;
    const VirtualCamera cam = with_coins(s, {coin_at(s.coin, m, a, 1.0)});
    const double expected = std::pow(1 / (1 - m), a == CoinAffects::Both ? 4 : 2);
    EXPECT_NEAR(pixels_seeing(cam, s.coin, rho, n) / base, expected, 0.05 * expected) << name(a);
  }
}

TEST(CoinCamera, TwoCoinsSuperposeAsThePapersSum) {
  // Computed by hand from the undeformed camera-space ray and coin_weight:
  // p_d = p + sum w_i (p_c,i - p), d_d = normalize(d + sum w_i (normalize(p_c,i - p) - d)).
  const CamCase t = setups()[4];  // plane + normal
  for (CoinAffects a : {CoinAffects::Org, CoinAffects::Dir}) {
    const Vec3 c1 = t.coin, c2 = t.coin + Vec3{0.5, -0.3, 0.4};
    const VirtualCamera plain(t.parts());
    const VirtualCamera two =
        with_coins(t, {coin_at(c1, 0.4, a, 0.3, 0.7), coin_at(c2, 0.35, a, 0.25, 2.0)});
    ASSERT_EQ(two.coins().sites().size(), 2u);
    int both = 0;
    for (int y = 0; y < 40; ++y)
      for (int x = 0; x < 40; ++x) {
        const Vec2 uv{(x + 0.5) / 40, (y + 0.5) / 40};
        const auto r0 = plain.generate_pinhole(uv), r = two.generate_pinhole(uv);
        ASSERT_TRUE(r0 && r);
        Vec3 p = r0->org, d = r0->dir;
        int n = 0;
        for (const CoinSite& c : two.coins().sites()) {
          const double w = coin_weight(c.strength, length(c.p_camera - r0->org), length(uv - c.uv),
                                       c.stiffness, c.radius, c.lc, c.falloff);
          n += w != 0;
          if (a == CoinAffects::Org)
            p = p + (c.p_camera - r0->org) * w;
          else
            d = d + (normalize(c.p_camera - r0->org) - r0->dir) * w;
        }
        both += n == 2;
        d = normalize(d);
        EXPECT_NEAR(length(r->org - p), 0, 1e-12) << name(a) << " uv " << str(uv);
        EXPECT_NEAR(length(r->dir - d), 0, 1e-12) << name(a) << " uv " << str(uv);
      }
    EXPECT_GT(both, 10) << "the two coins must overlap somewhere";
  }
}

TEST(CoinCamera, DifferentialsMatchFiniteDifferences) {
  for (const CamCase& s : setups())
    for (CoinAffects a : kAffects) {
      const VirtualCamera cam = with_coins(s, {coin_at(s.coin, 0.7, a, 0.3, 0.6)});
      const Vec2 c = cam.coins().sites()[0].uv;
      for (Vec2 off : {Vec2{0.05, 0.03}, Vec2{-0.11, 0.07}, Vec2{0.02, -0.15}}) {
        const Vec2 uv = c + off;
        const double h = 1e-6;
        const auto r = cam.generate_pinhole(uv);
        const auto ru0 = cam.generate_pinhole({uv.x - h, uv.y}),
                   ru1 = cam.generate_pinhole({uv.x + h, uv.y});
        const auto rv0 = cam.generate_pinhole({uv.x, uv.y - h}),
                   rv1 = cam.generate_pinhole({uv.x, uv.y + h});
        ASSERT_TRUE(r && ru0 && ru1 && rv0 && rv1) << s.label << " " << str(uv);
        const auto check = [&](const Vec3& analytic, const Vec3& fd, const char* what) {
          EXPECT_LT(length(analytic - fd), 2e-5 * (1 + length(fd)))
              << s.label << " " << name(a) << " " << what << " at " << str(uv) << ": analytic "
              << str(analytic) << " finite difference " << str(fd);
        };
        check(r->dorg_du, (ru1->org - ru0->org) / (2 * h), "dorg/du");
        check(r->dorg_dv, (rv1->org - rv0->org) / (2 * h), "dorg/dv");
        check(r->ddir_du, (ru1->dir - ru0->dir) / (2 * h), "ddir/du");
        check(r->ddir_dv, (rv1->dir - rv0->dir) / (2 * h), "ddir/dv");
      }
    }
}

TEST(CoinCamera, OrgAndDirAreDeformedIndependently) {
  // The paper's model: org(u,v) and dir(u,v) are the functions' values (dir = normal reads the
  // undeformed surface), then each is deformed by its own formula. An org coin leaves directions
  // bit-identical, a dir coin leaves origins bit-identical, and "both" combines the two.
  for (const CamCase& s : setups()) {
    const VirtualCamera org = with_coins(s, {coin_at(s.coin, 0.6, CoinAffects::Org, 0.3)});
    const VirtualCamera dir = with_coins(s, {coin_at(s.coin, 0.6, CoinAffects::Dir, 0.3)});
    const VirtualCamera both = with_coins(s, {coin_at(s.coin, 0.6, CoinAffects::Both, 0.3)});
    const Vec2 c = org.coins().sites()[0].uv;
    for (Vec2 off : {Vec2{0.1, 0.0}, Vec2{0.05, 0.12}, Vec2{-0.15, -0.1}}) {
      const auto ro = org.generate_pinhole(c + off), rd = dir.generate_pinhole(c + off),
                 rb = both.generate_pinhole(c + off);
      ASSERT_TRUE(ro && rd && rb) << s.label;
      EXPECT_EQ(std::memcmp(&ro->dir, &rb->dir, sizeof(Vec3)) == 0, false) << s.label;
      EXPECT_TRUE(std::memcmp(&ro->org, &rb->org, sizeof(Vec3)) == 0) << s.label << str(c + off);
      EXPECT_TRUE(std::memcmp(&rd->dir, &rb->dir, sizeof(Vec3)) == 0) << s.label << str(c + off);
      const VirtualCamera plain(s.parts());
      const auto r0 = plain.generate_pinhole(c + off);
      // Affine fields under a coin come from their closed form: equal up to rounding.
      EXPECT_LT(length(r0->dir - ro->dir), 1e-14) << s.label << str(c + off);
      EXPECT_LT(length(r0->org - rd->org), 1e-14 * (1 + length(r0->org)))
          << s.label << str(c + off);
    }
  }
}

TEST(CoinCamera, CoinSitsWhereTheUndistortedCameraSeesIt) {
  for (const CamCase& s : setups()) {
    const VirtualCamera plain(s.parts());
    const auto uvs = plain.project(s.coin);
    ASSERT_EQ(uvs.size(), 1u) << s.label;
    for (CoinAffects a : kAffects) {
      const VirtualCamera cam = with_coins(s, {coin_at(s.coin, 0.5, a)});
      const CoinSite& site = cam.coins().sites()[0];
      EXPECT_NEAR(length(site.uv - uvs[0]), 0, 1e-12) << s.label;
      const auto pin = plain.generate_pinhole(site.uv);
      EXPECT_NEAR(site.lc, length(site.p_camera - pin->org), 1e-12) << s.label;
      // (uc, vc) is a fixed point: its ray still passes through the coin.
      const auto r = test::ray(cam, site.uv);
      ASSERT_TRUE(r);
      const Vec3 op = s.coin - r->org;
      EXPECT_LT(length(op - r->dir * dot(op, r->dir)), 1e-9 * length(op))
          << s.label << " " << name(a);
    }
  }
}

TEST(CoinCamera, ProjectIncludesTheCoins) {
  // pixel -> ray -> point -> project: the pixel comes back, through the distorted camera.
  for (const CamCase& s : setups())
    for (CoinAffects a : kAffects) {
      const VirtualCamera cam = with_coins(s, {coin_at(s.coin, 0.6, a, 0.3)});
      const Vec2 c = cam.coins().sites()[0].uv;
      for (Vec2 off : {Vec2{0, 0}, Vec2{0.04, 0.02}, Vec2{-0.1, 0.08}, Vec2{0.2, -0.05}}) {
        const Vec2 uv = c + off;
        const auto r = test::ray(cam, uv);
        ASSERT_TRUE(r);
        const Vec3 p = r->org + r->dir * 3.0;
        const auto back = cam.project(p);
        bool found = false;
        for (const Vec2& q : back) found |= length(q - uv) < 1e-6;
        EXPECT_TRUE(found) << s.label << " " << name(a) << " uv " << str(uv) << " point " << str(p)
                           << " projects to " << test::str(back);
      }
    }
}

TEST(CoinCamera, EveryAppearanceOfACoinCarriesIt) {
  // An omnidirectional stereo pair sees the coin once per eye; a light-field quilt once per view.
  const std::string rig = "look_from = [0, 0, 0]\nlook_at = [0, 0, -1]\nup = [0, 1, 0]\n";
  for (auto [preset, toml, img] :
       {std::tuple{"ods", std::string(rig), ImageInfo{512, 512}},
        std::tuple{"light_field",
                   std::string("look_from = [0, 0, 0]\nlook_at = [0, 0, -5]\nup = [0, 1, 0]\n"
                               "columns = 3\nrows = 2"),
                   ImageInfo{600, 400}}}) {
    const Vec3 coin{0.3, 0.2, -5};
    const VirtualCamera plain(make_preset(preset, toml, img));
    const auto uvs = plain.project(coin);
    ASSERT_GE(uvs.size(), 2u) << preset;
    VirtualCameraParts p = make_preset(preset, toml, img);
    p.coins = {coin_at(coin, 0.5, CoinAffects::Dir, 0.05)};
    const VirtualCamera cam(std::move(p));
    ASSERT_EQ(cam.coins().sites().size(), uvs.size()) << preset;
    for (const CoinSite& site : cam.coins().sites()) {
      const Vec2 uv = site.uv + Vec2{0.01, 0.01};
      const auto r0 = test::ray(plain, uv), r1 = test::ray(cam, uv);
      ASSERT_TRUE(r0 && r1);
      EXPECT_GT(length(r0->dir - r1->dir), 1e-4) << preset << " appearance at " << str(site.uv);
    }
  }
}

TEST(CoinCamera, UnseenCoinWarnsAndChangesNothing) {
  const CamCase s = setups()[0];
  const VirtualCamera plain(s.parts());
  const VirtualCamera cam = with_coins(s, {coin_at({1, 2, 10}, 0.5)});  // behind the camera
  EXPECT_TRUE(cam.coins().empty());
  ASSERT_EQ(cam.coin_warnings().size(), 1u);
  EXPECT_NE(cam.coin_warnings()[0].find("coin[0]"), std::string::npos) << cam.coin_warnings()[0];
  const Rays a = ray_grid(plain, 32, 24), b = ray_grid(cam, 32, 24);
  for (size_t i = 0; i < a.size(); ++i) ASSERT_TRUE(bit_identical(a[i], b[i])) << i;
}

TEST(CoinCamera, GridFindsExactlyTheCoinsThatReachASample) {
  // 300 coins of random radii on a grid-of-spheres camera; the grid's answer against all sites.
  const CamCase s = setups()[3];  // equirectangular: sees every direction
  Rng rng(11, 1);
  std::vector<Coin> coins;
  for (int i = 0; i < 300; ++i) {
    const Vec3 dir = normalize(Vec3{rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5});
    coins.push_back(coin_at(Vec3{1, 2, 3} + dir * (2 + 3 * rng.uniform()),
                            0.01 + 0.02 * rng.uniform(), CoinAffects::Dir,
                            0.002 + 0.05 * rng.uniform() * rng.uniform()));
  }
  const VirtualCamera cam = with_coins(s, coins);
  ASSERT_EQ(cam.coins().sites().size(), 300u);
  EXPECT_GT(cam.coins().grid_size(), 10);
  for (int i = 0; i < 20000; ++i) {
    const Vec2 uv{rng.uniform() * 1.2 - 0.1, rng.uniform() * 1.2 - 0.1};
    bool brute = false;
    for (const CoinSite& c : cam.coins().sites()) brute |= length(uv - c.uv) < c.radius;
    ASSERT_EQ(cam.coins().reaches(uv), brute) << str(uv);
  }
  EXPECT_FALSE(cam.coins().reaches({std::nan(""), 0.5}));
}

// The vectorized packet path against one ray at a time: same bits, lanes no coin reaches
// untouched, may_reach never false where a lane is reached; tight packets (pixel neighbours) and
// scattered ones (more coins at once than the packet's candidate list holds).
TEST(CoinCamera, PacketsDeformExactlyLikeSingleRays) {
  const CamCase s = setups()[3];
  Rng rng(5, 2);
  std::vector<Coin> coins;
  constexpr CoinFalloff kFalloffs[] = {CoinFalloff::Smooth, CoinFalloff::Quadratic,
                                       CoinFalloff::Gaussian};
  for (int i = 0; i < 300; ++i) {
    const Vec3 dir = normalize(Vec3{rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5});
    coins.push_back(coin_at(Vec3{1, 2, 3} + dir * (2 + 3 * rng.uniform()),
                            0.05 + 0.1 * rng.uniform(), kAffects[i % 3], 0.02 + 0.1 * rng.uniform(),
                            0.5 + rng.uniform(), kFalloffs[(i / 3) % 3]));
  }
  const VirtualCamera plain(s.parts()), cam = with_coins(s, coins);
  const CoinField& field = cam.coins();
  int reached_lanes = 0, packets_reached = 0;
  for (int packet = 0; packet < 400; ++packet) {
    const bool scattered = packet % 4 == 3;
    const double u0 = rng.uniform(), v0 = rng.uniform();
    double u[kCameraBatch], v[kCameraBatch];
    CameraRayBatch batch;
    for (int k = 0; k < kCameraBatch; ++k) {
      u[k] = scattered ? rng.uniform() : std::min(1.0, u0 + (k % 4) * 0.002);
      v[k] = scattered ? rng.uniform() : std::min(1.0, v0 + (k / 4) * 0.002);
      batch.set(k, plain.generate_pinhole({u[k], v[k]}));
    }
    const CameraRayBatch before = batch;
    bool reached[kCameraBatch], any = false;
    field.apply_batch(u, v, kCameraBatch, &batch, reached);
    for (int k = 0; k < kCameraBatch; ++k) {
      std::ostringstream where;
      where.precision(17);
      where << "packet " << packet << " lane " << k << " at (" << u[k] << ", " << v[k] << ")";
      const std::string at = where.str();
      ASSERT_EQ(reached[k], field.reaches({u[k], v[k]})) << at;
      any |= reached[k];
      reached_lanes += reached[k];
      std::optional<CameraRay> one = before.ray(k);
      if (before.valid[k] && !field.apply({u[k], v[k]}, &*one)) one.reset();
      const std::optional<CameraRay> got =
          batch.valid[k] ? std::optional(batch.ray(k)) : std::nullopt;
      ASSERT_TRUE(bit_identical(got, before.valid[k] ? one : std::nullopt)) << at;
      if (!reached[k]) {
        ASSERT_TRUE(
            bit_identical(got, before.valid[k] ? std::optional(before.ray(k)) : std::nullopt))
            << at << " (not reached, must be untouched)";
      }
    }
    packets_reached += any;
    if (any) {
      ASSERT_TRUE(field.may_reach(u, v, kCameraBatch)) << "packet " << packet;
    }
  }
  // The cases above really happen.
  EXPECT_GT(packets_reached, 100);
  EXPECT_GT(reached_lanes, 1000);
}

// Any number of coins may reach one sample (the paper sums them all). Regression: more than 64
// at one sample overflowed the packet's candidate list and recursed until the stack ran out
// (65 coincident coins under an 8x8 perspective; 100 random ones under a 180 degree fisheye).
// For random sets up to 10,000 coins, coincident, overlapping, at the eye and on the image
// surface: packets give the bits of single rays, and every ray is finite with a unit direction.
struct CoinSetCase {
  std::string label;
  int camera;  // index into setups()
  int count;
  int pixels;  // image side for the comparison
};

std::vector<Coin> random_coin_set(const CoinSetCase& k, const CamCase& s, Rng& rng) {
  std::vector<Coin> coins;
  const Vec3 eye{1, 2, 3};
  for (int i = 0; i < k.count; ++i) {
    const double m = (rng.uniform() - 0.3) * 0.9;  // some repel, some sum past 1
    const CoinAffects a = kAffects[i % 3];
    const CoinFalloff f = kFalloffs[(i / 3) % 3];
    Vec3 p;
    switch (i % 5) {
      case 0:  // coincident: all at the case's coin
        p = s.coin;
        break;
      case 1:  // at the eye (the camera's origin)
        p = eye;
        break;
      case 2:  // on the plane camera's image surface (z = 3), elsewhere just near the eye
        p = Vec3{1 + 4 * (rng.uniform() - 0.5), 2 + 3 * (rng.uniform() - 0.5), 3};
        break;
      default:  // a cluster around the case's coin
        p = s.coin + Vec3{rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5};
    }
    coins.push_back(coin_at(p, m, a, 0.01 + 0.49 * rng.uniform(), 0.2 + 2 * rng.uniform(), f));
  }
  return coins;
}

TEST(CoinCamera, AnyNumberOfCoinsPacketsEqualSingleRaysAndStayFinite) {
  const std::vector<CamCase> cams = setups();
  const CoinSetCase cases[] = {
      {"65 coincident, perspective", 0, 65, 8}, {"100, fisheye", 1, 100, 12},
      {"300, plane + normal", 4, 300, 10},      {"2000, equirectangular", 3, 2000, 8},
      {"10000, perspective", 0, 10000, 4},
  };
  Rng rng(2026, 18);
  for (const CoinSetCase& k : cases) {
    const CamCase& s = cams[size_t(k.camera)];
    std::vector<Coin> coins = random_coin_set(k, s, rng);
    if (k.label.find("coincident") != std::string::npos)
      for (Coin& c : coins) c.position = s.coin, c.strength = 0.01, c.radius = 0.3;
    const VirtualCamera cam = with_coins(s, coins);
    const int n = k.pixels;
    std::vector<CameraSample> samples;
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) samples.push_back({{(x + 0.5) / n, (y + 0.5) / n}});
    int rays = 0;
    for (size_t b = 0; b < samples.size(); b += kCameraBatch) {
      const int m = int(std::min<size_t>(kCameraBatch, samples.size() - b));
      CameraRayBatch batch;
      cam.generate_batch(&samples[b], m, &batch);
      for (int i = 0; i < m; ++i) {
        const Vec2 uv = samples[b + size_t(i)].uv;
        const std::string at = k.label + " at " + str(uv);
        const std::optional<CameraRay> one = test::ray(cam, uv);
        const std::optional<CameraRay> got =
            batch.valid[i] ? std::optional(batch.ray(i)) : std::nullopt;
        ASSERT_TRUE(bit_identical(got, one)) << at;
        if (!one) continue;
        ++rays;
        ASSERT_TRUE(is_finite(one->org) && is_finite(one->dir)) << at << ": " << str(one->dir);
        ASSERT_NEAR(length(one->dir), 1, 1e-9) << at;
        for (const Vec3& d : {one->dorg_du, one->dorg_dv, one->ddir_du, one->ddir_dv})
          ASSERT_TRUE(is_finite(d)) << at << ": differential " << str(d);
      }
    }
    EXPECT_GT(rays, n * n / 4) << k.label << ": most samples still give a ray";
  }
}

// The same as a scene through the command line: 65 coins at one position used to crash `rays`
// and `render` with a stack overflow.
TEST(CoinScene, SixtyFiveCoincidentCoinsRender) {
  std::string toml =
      "[image]\nwidth = 8\nheight = 8\n[camera]\npreset = \"perspective\"\n"
      "look_from = [0, 0, 0]\nlook_at = [0, 0, -1]\n";
  for (int i = 0; i < 65; ++i) toml += "[[camera.coin]]\nposition = [0, 0, -3]\n";
  const Scene scene = load_scene_from_string(toml, "coins65.toml");
  int rays = 0;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x)
      rays += bool(test::ray(*scene.camera, {(x + 0.5) / 8, (y + 0.5) / 8}));
  EXPECT_EQ(rays, 64);
}

TEST(CoinOverlay, MarksCentersAndRadii) {
  const CamCase s = setups()[0];
  const VirtualCamera cam = with_coins(s, {coin_at(s.coin, 0.5, CoinAffects::Both, 0.2)});
  const CoinSite& c = cam.coins().sites()[0];
  const Vec2 px{1.0 / 400, 1.0 / 300};
  EXPECT_EQ(coin_overlay(cam, c.uv, px), 1.0);
  EXPECT_EQ(coin_overlay(cam, c.uv + Vec2{2 * px.x, 0}, px), 1.0);
  EXPECT_EQ(coin_overlay(cam, c.uv + Vec2{0.2, 0}, px), 1.0);  // on the circle
  EXPECT_EQ(coin_overlay(cam, c.uv + Vec2{0, -0.2}, px), 1.0);
  EXPECT_EQ(coin_overlay(cam, c.uv + Vec2{0.1, 0}, px), 0.0);  // between
  EXPECT_EQ(coin_overlay(cam, c.uv + Vec2{0.2 + 3 * px.x, 0}, px), 0.0);
  const double edge = coin_overlay(cam, c.uv + Vec2{0.2 + 0.75 * px.x, 0}, px);
  EXPECT_GT(edge, 0.0);
  EXPECT_LT(edge, 1.0);
  ASSERT_EQ(coin_sites(cam).size(), 1u);
  EXPECT_EQ(coin_sites(cam)[0].uv, c.uv);
}

// ---- the scene reader
// ------------------------------------------------------------------------------

const std::string kScene =
    "[image]\nwidth = 120\nheight = 90\n[render]\nintegrator = \"id\"\nsampler = \"center\"\nspp = "
    "1\n"
    "[camera]\nlook_from = [0, 0, 5]\nlook_at = [0, 0, 0]\nfov = 60\n"
    "[[camera.coin]]\nposition = [0.8, 0.4, 0]\nstrength = 0.5\nstiffness = 1.5\nradius = 0.3\n"
    "affects = \"org\"\nfalloff = \"gaussian\"\n"
    "[[object]]\ntype = \"sphere\"\ncenter = [0.8, 0.4, 0]\nradius = 0.15\n";

std::string scene_error(const std::string& toml, const std::vector<std::string>& set = {}) {
  try {
    load_scene_from_string(toml, "coins.toml", set);
  } catch (const SceneError& e) {
    return e.key + ": " + e.what();
  }
  return "(no error)";
}

TEST(CoinScene, ReadsCoinsWithEveryKey) {
  const Scene s = load_scene_from_string(kScene, "coins.toml");
  const auto sites = coin_sites(*s.camera);
  ASSERT_EQ(sites.size(), 1u);
  EXPECT_EQ(sites[0].strength, 0.5);
  EXPECT_EQ(sites[0].stiffness, 1.5);
  EXPECT_EQ(sites[0].radius, 0.3);
  EXPECT_EQ(sites[0].affects, CoinAffects::Org);
  EXPECT_EQ(sites[0].falloff, CoinFalloff::Gaussian);
  EXPECT_GT(sites[0].uv.x, 0.5);
  EXPECT_LT(sites[0].uv.y, 0.5);
  EXPECT_NE(s.camera->describe().find("1 coin"), std::string::npos) << s.camera->describe();
}

TEST(CoinScene, ErrorsNameTheKey) {
  const std::string base =
      "[camera]\n[[camera.coin]]\nposition = [0, 0, -5]\n[[camera.coin]]\nposition = [0, 0, -4]\n";
  struct Case {
    std::string extra, key;
  };
  for (const Case& c :
       std::vector<Case>{{"radius = 0", "camera.coin[1].radius"},
                         {"radius = 2.5", "camera.coin[1].radius"},
                         {"stiffness = 0", "camera.coin[1].stiffness"},
                         {"strength = 1.5", "camera.coin[1].strength"},
                         {"strength = -0.95\nstiffness = 10", "camera.coin[1].strength"},
                         {"affects = \"origin\"", "camera.coin[1].affects"},
                         {"falloff = \"box\"", "camera.coin[1].falloff"},
                         {"strenght = 0.2", "camera.coin[1].strenght"}}) {
    const std::string err = scene_error(base + c.extra + "\n");
    EXPECT_EQ(err.rfind(c.key + ":", 0), 0u) << c.extra << " -> " << err;
  }
  EXPECT_NE(
      scene_error("[camera]\n[[camera.coin]]\nstrength = 0.5\n").find("camera.coin[0].position"),
      std::string::npos);
  EXPECT_NE(scene_error("[camera]\ncoin = 3\n").find("camera.coin"), std::string::npos);
  const std::string choices = scene_error(base + "affects = \"origin\"\n");
  EXPECT_NE(choices.find("org"), std::string::npos) << choices;
  EXPECT_NE(choices.find("both"), std::string::npos) << choices;
}

TEST(CoinScene, SetReachesCoinsAndStrengthZeroRestoresTheCamera) {
  const std::string plain_scene =
      kScene.substr(0, kScene.find("[[camera.coin]]")) + kScene.substr(kScene.find("[[object]]"));
  const Scene plain = load_scene_from_string(plain_scene, "plain.toml");
  const Scene zero = load_scene_from_string(kScene, "coins.toml", {"camera.coin.0.strength=0"});
  EXPECT_TRUE(coin_sites(*zero.camera).empty());
  for (int y = 0; y < 90; y += 3)
    for (int x = 0; x < 120; x += 3) {
      const Vec2 uv{(x + 0.5) / 120, (y + 0.5) / 90};
      ASSERT_TRUE(bit_identical(test::ray(*plain.camera, uv), test::ray(*zero.camera, uv)));
    }
  const Scene radius = load_scene_from_string(kScene, "coins.toml", {"camera.coin.0.radius=0.1"});
  EXPECT_EQ(coin_sites(*radius.camera)[0].radius, 0.1);
  // A coin the camera does not see is reported with its key.
  const Scene behind =
      load_scene_from_string(kScene, "coins.toml", {"camera.coin.0.position=[0, 0, 9]"});
  bool warned = false;
  for (const auto& w : behind.warnings) warned |= w.rfind("camera.coin[0]", 0) == 0;
  EXPECT_TRUE(warned);
  // Switching the preset on the command line keeps the coins.
  const Scene fish = load_scene_from_string(kScene, "coins.toml", {"camera.preset=fisheye"});
  EXPECT_EQ(coin_sites(*fish.camera).size(), 1u);
}

TEST(CoinScene, RenderedObjectAtTheCoinGrowsWithStrength) {
  // Counted with the renderer: the `id` integrator colours the sphere at the coin; the
  // background is black.
  int prev = 0;
  for (const char* m : {"0", "0.3", "0.6", "0.85"}) {
    const auto r = test::render_text(kScene, {std::string("camera.coin.0.strength=") + m});
    int count = 0;
    for (int y = 0; y < r.film->height(); ++y)
      for (int x = 0; x < r.film->width(); ++x) count += max_component(r.film->pixel(x, y)) > 0;
    EXPECT_GT(count, prev) << "strength " << m;
    prev = count;
  }
}

TEST(CoinDocs, ParameterTableMatchesTheSpecs) {
  // docs/coins.md lists every key of [[camera.coin]] with its default, as the parser knows them.
  std::ifstream in(test::source_dir() / "docs" / "coins.md");
  ASSERT_TRUE(in) << "docs/coins.md not found";
  std::vector<std::string> rows;
  for (std::string line; std::getline(in, line);)
    if (line.rfind("| `", 0) == 0) rows.push_back(line);
  for (const ParamSpec& spec : coin_params()) {
    const std::string head = "| `" + std::string(spec.name) + "` |";
    const std::string def =
        spec.default_value.empty() ? "required" : "`" + std::string(spec.default_value) + "`";
    bool found = false;
    for (const std::string& row : rows)
      if (row.rfind(head, 0) == 0) {
        found = true;
        EXPECT_NE(row.find(def), std::string::npos)
            << spec.name << ": expected default " << def << " in\n"
            << row;
      }
    EXPECT_TRUE(found) << spec.name << " is missing from the table in docs/coins.md";
  }
}

}  // namespace
}  // namespace anamorph
