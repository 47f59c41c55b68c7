#include "render/adaptive.h"

#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "math/rng.h"

namespace anamorph {

namespace {

// The larger singular value of the pixel's footprint Jacobian [a b] (3x2) at distance D.
double footprint(const Vec3& a, const Vec3& b) {
  const double aa = dot(a, a), bb = dot(b, b), ab = dot(a, b);
  const double tr = aa + bb, det = std::max(0.0, aa * bb - ab * ab);
  return std::sqrt(0.5 * (tr + std::sqrt(std::max(0.0, tr * tr - 4 * det))));
}

}  // namespace

AdaptiveGrid::AdaptiveGrid(const Camera& cam, int width, int height, const RenderSettings& rs,
                           const Bounds3& bounds)
    : w_(width),
      h_(height),
      depth_(rs.aa_depth),
      steps_(1 << rs.aa_depth),
      threshold_(rs.aa_threshold),
      forced_(size_t(width) * height, 0) {
  if (!rs.aa_distortion || depth_ == 0) return;
  // Footprints at a characteristic distance: the scene's size (origins and directions both count).
  const double D = bounds.empty() ? 1.0 : std::max(1e-6, 0.5 * length(bounds.diagonal()));
  const size_t n = size_t(w_) * h_;
  std::vector<double> s(n, 0.0);
  std::vector<uint8_t> valid(n, 0), jump_right(n, 0), jump_down(n, 0);
  // Bands of rows in parallel, pixel centers in camera batches (the same rays as one at a time).
  // A band walks its rows keeping the current and the next one for the jump test, so no
  // image-sized arrays of points and derivatives are needed (at 1080p those were 150 MB of page
  // faults).
  struct Center {
    Vec3 pos, pu, pv;
    double s = 0;
    bool valid = false;
  };
  const auto centers = [&](int y, std::vector<Center>& row) {
    CameraSample cs[kCameraBatch];
    CameraRayBatch b;
    for (int x0 = 0; x0 < w_; x0 += kCameraBatch) {
      const int m = std::min(kCameraBatch, w_ - x0);
      for (int k = 0; k < m; ++k) cs[k].uv = {(x0 + k + 0.5) / w_, (y + 0.5) / h_};
      cam.generate_batch(cs, m, &b);
      for (int k = 0; k < m; ++k) {
        Center& c = row[size_t(x0 + k)];
        c.valid = b.valid[k];
        if (!c.valid) continue;
        const CameraRay r = b.ray(k);
        c.pos = r.org + r.dir * D;
        c.pu = (r.dorg_du + r.ddir_du * D) / double(w_);
        c.pv = (r.dorg_dv + r.ddir_dv * D) / double(h_);
        c.s = footprint(c.pu, c.pv);
      }
    }
  };
  // Jumps: a neighbour far from where the differentials predict it (seams of piecewise cameras,
  // discontinuous free-form surfaces) means the pixels in between need every level.
  const auto jump = [](const Center& a, const Center& b, const Vec3& predicted) {
    return a.valid && b.valid && length(b.pos - a.pos - predicted) > 2 * std::max(a.s, b.s);
  };
  tbb::parallel_for(tbb::blocked_range<int>(0, h_, 16), [&](const tbb::blocked_range<int>& band) {
    std::vector<Center> row(static_cast<size_t>(w_)), next(static_cast<size_t>(w_));
    centers(band.begin(), row);
    for (int y = band.begin(); y != band.end(); ++y) {
      if (y + 1 < h_) centers(y + 1, next);
      for (int x = 0; x < w_; ++x) {
        const size_t i = size_t(y) * w_ + x;
        const Center& c = row[size_t(x)];
        s[i] = c.s;
        valid[i] = c.valid;
        if (x + 1 < w_) jump_right[i] = jump(c, row[size_t(x) + 1], c.pu);
        if (y + 1 < h_) jump_down[i] = jump(c, next[size_t(x)], c.pv);
      }
      row.swap(next);
    }
  });
  std::vector<double> vals;
  for (size_t i = 0; i < n; ++i)
    if (valid[i] && s[i] > 0) vals.push_back(s[i]);
  if (vals.empty()) return;
  std::nth_element(vals.begin(), vals.begin() + long(vals.size() / 2), vals.end());
  const double median = vals[vals.size() / 2];
  tbb::parallel_for(0, h_, [&](int y) {
    for (int x = 0; x < w_; ++x) {
      const size_t i = size_t(y) * w_ + x;
      if (valid[i] && s[i] > 0)
        forced_[i] =
            uint8_t(std::clamp(int(std::floor(std::log2(s[i] / median) + 0.5)), 0, depth_));
      if (jump_right[i] || jump_down[i] || (x > 0 && jump_right[i - 1]) ||
          (y > 0 && jump_down[i - size_t(w_)]))
        forced_[i] = uint8_t(depth_);
    }
  });
}

void AdaptiveGrid::render_tile(int x0, int y0, int x1, int y1, AdaptiveWorkspace& ws,
                               const Eval& eval, const Emit& emit, uint64_t& rays,
                               const EvalCorners* corners) const {
  const int L = steps_;
  const int nx = (x1 - x0) * L + 1, ny = (y1 - y0) * L + 1;
  if (ws.points.size() < size_t(nx) * ny) ws.points.resize(size_t(nx) * ny);
  if (++ws.tile == 0) {  // the counter wrapped: forget everything once
    std::fill(ws.points.begin(), ws.points.end(), AdaptiveWorkspace::Point{});
    ws.tile = 1, ws.stamp = 0;
  }
  const uint32_t tile = ws.tile;
  const double su = 1.0 / (double(w_) * L), sv = 1.0 / (double(h_) * L);
  const uint64_t row = uint64_t(w_) * L + 1;
  const auto store = [tile](AdaptiveWorkspace::Point& p, const SampleResult& r) {
    p.nan = !is_finite(r.L);
    p.L = p.nan ? Color{} : r.L;
    p.alpha = float(r.alpha);
    p.tile = tile;
    p.stamp = 0;  // counted by no pixel yet (stamps start at 1)
  };

  // Pixel corners (cx, cy) in [x0, x1] x [y0, y1], in 4x4 blocks aligned to the image: camera
  // batches and ray packets, and the same lanes in every tile that needs the block. Lanes of
  // another tile's corners are masked off (a tile's last column and row of corners start a block
  // of their own: without the mask a 32-pixel tile shaded 81 blocks, 1296 corners, for 1089).
  if (corners)
    for (int by = y0 / 4 * 4; by <= y1; by += 4)
      for (int bx = x0 / 4 * 4; bx <= x1; bx += 4) {
        Vec2 uv[kCameraBatch];
        uint64_t keys[kCameraBatch];
        bool use[kCameraBatch];
        SampleResult out[kCameraBatch];
        for (int k = 0; k < kCameraBatch; ++k) {
          const int cx = bx + (k & 3), cy = by + (k >> 2);
          const uint64_t gx = uint64_t(cx) * L, gy = uint64_t(cy) * L;
          use[k] = cx <= w_ && cy <= h_ && cx >= x0 && cx <= x1 && cy >= y0 && cy <= y1;
          uv[k] = use[k] ? Vec2{gx * su, gy * sv} : Vec2{0.5, 0.5};
          keys[k] = mix64(gy * row + gx);
        }
        (*corners)(uv, keys, use, out, rays);
        for (int k = 0; k < kCameraBatch; ++k) {
          const int cx = bx + (k & 3), cy = by + (k >> 2);
          if (use[k]) store(ws.points[size_t(cy - y0) * L * nx + size_t(cx - x0) * L], out[k]);
        }
      }
  uint32_t& stamp = ws.stamp;
  PixelResult acc;

  // Lattice point (lx, ly) relative to the tile; evaluated once, counted once per pixel.
  auto point = [&](int lx, int ly) -> const AdaptiveWorkspace::Point& {
    AdaptiveWorkspace::Point& p = ws.points[size_t(ly) * nx + lx];
    if (p.tile != tile) {
      const uint64_t gx = uint64_t(x0) * L + lx, gy = uint64_t(y0) * L + ly;
      // The coarsest level whose lattice holds this point (0 = pixel corners).
      auto level = [&](uint64_t g) {
        int k = depth_;
        while (k > 0 && g % 2 == 0) g /= 2, --k;
        return k;
      };
      const double footprint = 1.0 / double(1 << std::max(level(gx), level(gy)));
      store(p, eval({gx * su, gy * sv}, mix64(gy * row + gx), footprint, rays));
    }
    if (p.stamp != stamp) {
      p.stamp = stamp;
      acc.samples++;
      acc.nans += p.nan;
    }
    return p;
  };
  auto contrast = [&](const AdaptiveWorkspace::Point* c[4]) {
    double worst = 0;
    for (int k = 0; k < 3; ++k) {
      double lo = kInf, hi = -kInf;
      for (int i = 0; i < 4; ++i) {
        const double v = std::min(1.0, c[i]->L[k]);  // compare as displayed
        lo = std::min(lo, v), hi = std::max(hi, v);
      }
      worst = std::max(worst, hi - lo);
    }
    double alo = 1, ahi = 0;
    for (int i = 0; i < 4; ++i)
      alo = std::min(alo, double(c[i]->alpha)), ahi = std::max(ahi, double(c[i]->alpha));
    return std::max(worst, ahi - alo);
  };
  // Mean of a square of side `size` lattice steps; returns colour and alpha.
  // Recursive through its own parameter (a std::function cost ~6% of an adaptive render).
  const auto square = [&](const auto& self, int lx, int ly, int size, int forced, Color& col,
                          double& alpha) -> void {
    const AdaptiveWorkspace::Point* c[4] = {&point(lx, ly), &point(lx + size, ly),
                                            &point(lx, ly + size), &point(lx + size, ly + size)};
    if (size > 1 && (forced > 0 || contrast(c) > threshold_)) {
      const int h = size / 2;
      Color sum;
      double asum = 0;
      for (int k = 0; k < 4; ++k) {
        Color cc;
        double aa;
        self(self, lx + (k & 1) * h, ly + (k >> 1) * h, h, forced - 1, cc, aa);
        sum += cc;
        asum += aa;
      }
      col = sum * 0.25;
      alpha = asum * 0.25;
      return;
    }
    // Colours are averaged with their coverage, so a no-ray corner does not darken the pixel.
    Color sum;
    double asum = 0;
    for (const auto* p : c) sum += p->L * double(p->alpha), asum += p->alpha;
    col = sum * 0.25;
    alpha = asum * 0.25;
  };

  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      if (++stamp == 0) ++stamp;  // 0 marks points no pixel counted yet
      acc = PixelResult{};
      Color premul;
      double alpha;
      square(square, (x - x0) * L, (y - y0) * L, L, forced_depth(x, y), premul, alpha);
      acc.alpha = alpha;
      acc.L = premul;  // the film's sums are coverage-weighted colour
      emit(x, y, acc);
    }
}

size_t update_active(const Film& film, double threshold, std::vector<uint8_t>* active) {
  const int W = film.width(), H = film.height();
  std::vector<uint8_t> noisy(size_t(W) * H, 0);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const double mean = luminance(film.pixel(x, y));
      noisy[size_t(y) * W + x] =
          film.standard_error(x, y) > threshold * std::sqrt(std::max(0.0, mean) + 1e-4);
    }
  size_t n = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      uint8_t a = 0;
      for (int dy = -1; dy <= 1 && !a; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = x + dx, yy = y + dy;
          if (xx >= 0 && yy >= 0 && xx < W && yy < H && noisy[size_t(yy) * W + xx]) {
            a = 1;
            break;
          }
        }
      (*active)[size_t(y) * W + x] = a;
      n += a;
    }
  return n;
}

}  // namespace anamorph
