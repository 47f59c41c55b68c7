#include "render/adaptive.h"

#include <algorithm>
#include <cmath>

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
  std::vector<double> s(size_t(w_) * h_, 0.0);
  std::vector<Vec3> pos(size_t(w_) * h_), pu(size_t(w_) * h_), pv(size_t(w_) * h_);
  std::vector<uint8_t> valid(size_t(w_) * h_, 0);
  // Rows in parallel, pixel centers in camera batches (the same rays as one at a time): at 1080p
  // this pass took longer than rendering a fisheye image's samples.
  tbb::parallel_for(0, h_, [&](int y) {
    CameraSample cs[kCameraBatch];
    CameraRayBatch b;
    for (int x0 = 0; x0 < w_; x0 += kCameraBatch) {
      const int n = std::min(kCameraBatch, w_ - x0);
      for (int k = 0; k < n; ++k) cs[k].uv = {(x0 + k + 0.5) / w_, (y + 0.5) / h_};
      cam.generate_batch(cs, n, &b);
      for (int k = 0; k < n; ++k) {
        if (!b.valid[k]) continue;
        const CameraRay r = b.ray(k);
        const size_t i = size_t(y) * w_ + size_t(x0 + k);
        pos[i] = r.org + r.dir * D;
        pu[i] = (r.dorg_du + r.ddir_du * D) / double(w_);
        pv[i] = (r.dorg_dv + r.ddir_dv * D) / double(h_);
        s[i] = footprint(pu[i], pv[i]);
        valid[i] = 1;
      }
    }
  });
  std::vector<double> vals;
  for (size_t i = 0; i < s.size(); ++i)
    if (valid[i] && s[i] > 0) vals.push_back(s[i]);
  if (vals.empty()) return;
  std::nth_element(vals.begin(), vals.begin() + long(vals.size() / 2), vals.end());
  const double median = vals[vals.size() / 2];
  for (size_t i = 0; i < s.size(); ++i)
    if (valid[i] && s[i] > 0)
      forced_[i] = uint8_t(std::clamp(int(std::floor(std::log2(s[i] / median) + 0.5)), 0, depth_));
  // Jumps: a neighbour far from where the differentials predict it (seams of piecewise cameras,
  // discontinuous free-form surfaces) means the pixels in between need every level.
  for (int y = 0; y < h_; ++y)
    for (int x = 0; x < w_; ++x) {
      const size_t i = size_t(y) * w_ + x;
      if (!valid[i]) continue;
      auto check = [&](size_t j, const Vec3& predicted) {
        if (!valid[j]) return;
        const double err = length(pos[j] - pos[i] - predicted);
        if (err > 2 * std::max(s[i], s[j])) forced_[i] = forced_[j] = uint8_t(depth_);
      };
      if (x + 1 < w_) check(i + 1, pu[i]);
      if (y + 1 < h_) check(i + size_t(w_), pv[i]);
    }
}

void AdaptiveGrid::render_tile(int x0, int y0, int x1, int y1, AdaptiveWorkspace& ws,
                               const Eval& eval, const Emit& emit, uint64_t& rays) const {
  const int L = steps_;
  const int nx = (x1 - x0) * L + 1, ny = (y1 - y0) * L + 1;
  ws.points.assign(size_t(nx) * ny, AdaptiveWorkspace::Point{});
  const double su = 1.0 / (double(w_) * L), sv = 1.0 / (double(h_) * L);
  const uint64_t row = uint64_t(w_) * L + 1;
  uint32_t stamp = 0;
  PixelResult acc;

  // Lattice point (lx, ly) relative to the tile; evaluated once, counted once per pixel.
  auto point = [&](int lx, int ly) -> const AdaptiveWorkspace::Point& {
    AdaptiveWorkspace::Point& p = ws.points[size_t(ly) * nx + lx];
    if (!p.done) {
      const uint64_t gx = uint64_t(x0) * L + lx, gy = uint64_t(y0) * L + ly;
      // The coarsest level whose lattice holds this point (0 = pixel corners).
      auto level = [&](uint64_t g) {
        int k = depth_;
        while (k > 0 && g % 2 == 0) g /= 2, --k;
        return k;
      };
      const double footprint = 1.0 / double(1 << std::max(level(gx), level(gy)));
      const SampleResult r = eval({gx * su, gy * sv}, mix64(gy * row + gx), footprint, rays);
      p.nan = !is_finite(r.L);
      p.L = p.nan ? Color{} : r.L;
      p.alpha = float(r.alpha);
      p.done = true;
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
  std::function<void(int, int, int, int, Color&, double&)> square = [&](int lx, int ly, int size,
                                                                        int forced, Color& col,
                                                                        double& alpha) {
    const AdaptiveWorkspace::Point* c[4] = {&point(lx, ly), &point(lx + size, ly),
                                            &point(lx, ly + size), &point(lx + size, ly + size)};
    if (size > 1 && (forced > 0 || contrast(c) > threshold_)) {
      const int h = size / 2;
      Color sum;
      double asum = 0;
      for (int k = 0; k < 4; ++k) {
        Color cc;
        double aa;
        square(lx + (k & 1) * h, ly + (k >> 1) * h, h, forced - 1, cc, aa);
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
      ++stamp;
      acc = PixelResult{};
      Color premul;
      double alpha;
      square((x - x0) * L, (y - y0) * L, L, forced_depth(x, y), premul, alpha);
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
