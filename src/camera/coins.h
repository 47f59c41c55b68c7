// Centers of interest (coins): the paper's local nonlinear zoom. A coin is a world-space point
// that attracts the image surface (org) and/or bends the ray directions (dir) near the image
// position (uc, vc) where the undistorted camera sees it:
//
//   p_d = p + sum_i w_i (p_c,i - p),     d_d = normalize(d + sum_i w_i (normalize(p_c,i - p) - d))
//
// with the weight (docs/coins.md has the reasoning and plots)
//
//   w(m, l, d, s) = m * B_s(K(d^2 / R^2)) * A(l^2 / l_c^2)
//
//   K(x)   falloff kernel: K(0) = 1, decreasing, K = K' = 0 at x = 1 (exactly 0 beyond R)
//   B_s(y) = s y / (1 + (s - 1) y), the stiffness: low s keeps the deformation near (uc, vc)
//   A(z)   = 2 z / (1 + z^2), z = (l / l_c)^2: the coin pulls hardest on the image surface at its
//            own distance l_c (the distance to org(uc, vc)); it falls off with the inverse square
//            of l farther away and releases points that already sit at the coin.
//
// Every factor lies in [0, 1], so |w| <= |m| <= 1 and no point is pulled past its coin.
//
// As in the paper, coins act on the ray field the org and dir functions define: org(u,v) and
// dir(u,v) are evaluated as usual (dir reads the undeformed origin sample), then each is deformed
// by its formula, with the weights computed from the undeformed origin p.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "camera/functions.h"
#include "math/transform.h"
#include "math/vec.h"
#include "params/params.h"

namespace anamorph {

class Camera;
class VirtualCamera;
struct CameraRay;
struct CameraRayBatch;

enum class CoinAffects : uint8_t { Org = 1, Dir = 2, Both = 3 };
enum class CoinFalloff : uint8_t { Smooth, Quadratic, Gaussian };

// One [[camera.coin]] entry, as the user gives it.
struct Coin {
  Vec3 position;  // world space
  double strength =
      0.5;  // m: fraction of the way to the coin at (uc, vc); 0 = no effect, < 0 repels
  double stiffness = 1;  // s > 0: low = only close to (uc, vc), high = broad
  double radius = 0.25;  // R: radius of influence in (u, v); exactly no effect beyond it
  CoinAffects affects = CoinAffects::Both;
  CoinFalloff falloff = CoinFalloff::Smooth;
};

// The parameter table of a coin (scene parser, docs) and building a Coin from checked values.
// Throws ParamError naming the key (e.g. a repelling strength that would fold the image over).
std::span<const ParamSpec> coin_params();
Coin coin_from_params(const ParamValues& v);
// From TOML text holding some of the keys, e.g. make_coin("position = [0, 0, -5]"), for tests
// and tools.
Coin make_coin(std::string_view toml_text);

// ---- the weight, factor by factor (for tests, plots and docs) ----------------------------------

// A kernel value and its first and second derivatives with respect to x = (d / R)^2.
struct KernelValue {
  double k = 0, dk = 0, d2k = 0;
};
// Zero (with zero derivatives) for x >= 1.
KernelValue coin_kernel(CoinFalloff f, double x);
// B_s(y) and its derivatives with respect to y.
KernelValue coin_stiffness(double s, double y);
// A(z) and its derivatives with respect to z = (l / l_c)^2.
KernelValue coin_distance(double z);
// The paper's w(m, l, d, s) for a coin with radius R whose image surface point at (uc, vc) is at
// distance lc from it.
double coin_weight(double m, double l, double d, double s, double radius, double lc,
                   CoinFalloff f = CoinFalloff::Smooth);
// The most negative strength that keeps the image free of fold-over: in the radial model (a
// pinhole or any image surface at constant distance to the coin) the map r -> (1 - w(r)) r must
// stay increasing, i.e. 1 + |m| (t g(t))' > 0 with g = B_s(K(t^2)). -1 when nothing folds.
double coin_min_strength(double stiffness, CoinFalloff f);

// ---- the coins of one camera ------------------------------------------------------------------

// One appearance of a coin in the image (a coin seen several times, e.g. in every view of a quilt
// or a stereo pair, has several).
struct CoinSite {
  int coin = 0;       // index into the camera's coin list ([[camera.coin]] order)
  Vec2 uv;            // (uc, vc): where the undistorted camera sees the coin
  double radius = 0;  // R in (u, v)
  double lc = 0;      // distance from the coin to the undeformed org(uc, vc)
  double strength = 0, stiffness = 1;
  CoinAffects affects = CoinAffects::Both;
  CoinFalloff falloff = CoinFalloff::Smooth;
  Vec3 p_camera;  // the coin in camera space (before the rig)
};

class CoinField {
 public:
  CoinField() = default;
  // Finds every coin's image positions with `project_world` (the undistorted camera's inverse
  // map) and its l_c with `org`; coins with strength 0 are dropped (so they change nothing, bit
  // for bit), coins the camera does not see get a warning ("coin[i]: ...") and no effect.
  CoinField(std::span<const Coin> coins, const Transform& camera_from_world,
            const std::function<std::vector<Vec2>(const Vec3&)>& project_world,
            const OrgFunction& org, std::vector<std::string>* warnings);

  bool empty() const { return sites_.empty(); }
  std::span<const CoinSite> sites() const { return sites_; }
  // Grid resolution over (u, v) (cells per side), for tests and the benchmark.
  int grid_size() const { return grid_; }

  // True when some coin's radius contains uv (its ray must be deformed).
  bool reaches(Vec2 uv) const;
  // False when no coin reaches any of the n positions (a test of their bounding box: true does
  // not mean that one does).
  bool may_reach(const double* u, const double* v, int n) const;
  // Deforms the camera-space pinhole ray at uv (unit direction, derivatives with respect to u and
  // v) by the coins that reach uv: the origin by the org formula, the direction by the dir
  // formula, with exact derivatives. Leaves the ray untouched (bit for bit) when no coin reaches
  // uv; false when the bent direction vanishes (no ray). Allocation-free, thread-safe.
  bool apply(Vec2 uv, CameraRay* r) const;
  // apply() for lanes 0..n-1 of a batch of camera-space rays at (u[i], v[i]), vectorized over
  // the lanes: reached[i] tells whether a coin reaches lane i (its ray is then deformed, or,
  // bent exactly backwards, marked invalid); lanes no coin reaches are untouched. apply() is
  // this with n = 1, so both give the same bits.
  void apply_batch(const double* u, const double* v, int n, CameraRayBatch* rays,
                   bool* reached) const;

  // Coverage in [0, 1] of the `--aov coins` markers at uv: a dot of 3 pixels radius at each
  // (uc, vc) and a 1.5 pixel wide outline of each radius of influence. `pixel` is the size of a
  // pixel in (u, v): (1 / width, 1 / height).
  double overlay(Vec2 uv, Vec2 pixel) const;

 private:
  // The constructor's steps.
  int add_sites(int index, const Coin& c, const Vec3& pc, const std::vector<Vec2>& uvs,
                const OrgFunction& org, const std::function<void(std::string)>& warn);
  void build_grid();
  std::string overlap_warning() const;
  // Calls f(site index) for every site stored in the grid cell of uv.
  template <class F>
  void for_cell(Vec2 uv, F&& f) const;

  struct Disk {  // the hot part of a site: the first test of every candidate
    double u, v, inv_r2;
  };
  std::vector<CoinSite> sites_;
  std::vector<Disk> disks_;
  std::vector<double> inv_lc2_;
  int grid_ = 0;
  std::vector<uint32_t> cell_start_, cell_items_;  // CSR: items of cell c in [start[c], start[c+1])
};

// For `anamorph info` and `--aov coins`: the camera's coin sites (empty without coins), and the
// marker coverage at an image position.
std::span<const CoinSite> coin_sites(const VirtualCamera& cam);
double coin_overlay(const VirtualCamera& cam, Vec2 uv, Vec2 pixel);

}  // namespace anamorph
