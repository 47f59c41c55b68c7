#include "render/adaptive.h"

#include <algorithm>
#include <cmath>

#include "math/parallel.h"
#include "math/rng.h"

namespace anamorph {

namespace {

// The larger singular value of the pixel's footprint Jacobian [a b] (3x2) at distance D.
double footprint(const Vec3& a, const Vec3& b) {
  const double aa = dot(a, a), bb = dot(b, b), ab = dot(a, b);
  const double tr = aa + bb, det = std::max(0.0, aa * bb - ab * ab);
  return std::sqrt(0.5 * (tr + std::sqrt(std::max(0.0, tr * tr - 4 * det))));
}

// The ray field at the lanes of a camera batch: position at distance D, its derivatives per
// pixel step, the footprint.
void corner_geometry(const CameraRayBatch& b, int k, double D, int w, int h,
                     AdaptiveWorkspace::Corner* c) {
  c->valid = b.valid[k];
  if (!c->valid) return;
  c->pos = b.origin(k) + b.direction(k) * D;
  c->pu = (CameraRayBatch::at(b.dorg_du, k) + CameraRayBatch::at(b.ddir_du, k) * D) / double(w);
  c->pv = (CameraRayBatch::at(b.dorg_dv, k) + CameraRayBatch::at(b.ddir_dv, k) * D) / double(h);
  c->s = footprint(c->pu, c->pv);
}

}  // namespace

AdaptiveGrid::AdaptiveGrid(const Camera& cam, int width, int height, const RenderSettings& rs,
                           const Bounds3& bounds)
    : w_(width),
      h_(height),
      depth_(rs.aa_depth),
      steps_(1 << rs.aa_depth),
      threshold_(rs.aa_threshold) {
  if (!rs.aa_distortion || depth_ == 0) return;
  // Footprints at a characteristic distance: the scene's size (origins and directions both count).
  distance_ = bounds.empty() ? 1.0 : std::max(1e-6, 0.5 * length(bounds.diagonal()));
  // The median corner footprint, from every 8th corner of every 8th row of corners (a fixed
  // sample of the image, so the same for any tiling or thread count).
  std::vector<int> xs;
  for (int x = std::min(4, w_); x <= w_; x += 8) xs.push_back(x);
  std::vector<int> ys;
  for (int y = std::min(4, h_); y <= h_; y += 8) ys.push_back(y);
  std::vector<std::vector<double>> per_row(ys.size());
  parallel_for_each(0, int(ys.size()), [&](int r) {
    CameraSample cs[kCameraBatch];
    CameraRayBatch b;
    AdaptiveWorkspace::Corner c;
    for (size_t k0 = 0; k0 < xs.size(); k0 += kCameraBatch) {
      const int m = int(std::min<size_t>(kCameraBatch, xs.size() - k0));
      for (int k = 0; k < m; ++k)
        cs[k].uv = {double(xs[k0 + size_t(k)]) / w_, double(ys[size_t(r)]) / h_};
      cam.generate_batch(cs, m, &b);
      for (int k = 0; k < m; ++k) {
        corner_geometry(b, k, distance_, w_, h_, &c);
        if (c.valid && c.s > 0) per_row[size_t(r)].push_back(c.s);
      }
    }
  });
  std::vector<double> vals;
  for (const auto& r : per_row) vals.insert(vals.end(), r.begin(), r.end());
  if (vals.empty()) return;
  std::nth_element(vals.begin(), vals.begin() + long(vals.size() / 2), vals.end());
  median_ = vals[vals.size() / 2];
  distortion_ = true;
}

void AdaptiveGrid::distortion_map(int x0, int y0, int x1, int y1, AdaptiveWorkspace& ws) const {
  const int tw = x1 - x0, cw = tw + 1;
  ws.forced.assign(size_t(tw) * (y1 - y0), 0);
  if (!distortion_) return;
  // A neighbour far from where the differentials predict it (seams of piecewise cameras,
  // discontinuous free-form surfaces) means the pixels along that edge need every level.
  const auto jump = [](const AdaptiveWorkspace::Corner& a, const AdaptiveWorkspace::Corner& b,
                       const Vec3& predicted) {
    return a.valid && b.valid && length(b.pos - a.pos - predicted) > 2 * std::max(a.s, b.s);
  };
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      const auto& c00 = ws.corners[size_t(y - y0) * cw + (x - x0)];
      const auto& c10 = (&c00)[1];
      const auto& c01 = (&c00)[cw];
      const auto& c11 = (&c00)[cw + 1];
      uint8_t& f = ws.forced[size_t(y - y0) * tw + (x - x0)];
      if (jump(c00, c10, c00.pu) || jump(c01, c11, c01.pu) || jump(c00, c01, c00.pv) ||
          jump(c10, c11, c10.pv)) {
        f = uint8_t(depth_);
        continue;
      }
      double s = 0;
      for (const auto* c : {&c00, &c10, &c01, &c11})
        if (c->valid) s = std::max(s, c->s);
      if (s > 0) f = uint8_t(std::clamp(int(std::floor(std::log2(s / median_) + 0.5)), 0, depth_));
    }
}

namespace {

// The largest spread of a channel (compared as displayed, clamped at 1) or of coverage.
double contrast(const AdaptiveWorkspace::Point* c[4]) {
  const auto spread = [](double a, double b, double d, double e) {
    const double lo = std::min(std::min(a, b), std::min(d, e));
    const double hi = std::max(std::max(a, b), std::max(d, e));
    return hi - lo;
  };
  const auto ch = [&](double Color::*m) {
    return spread(std::min(1.0, c[0]->L.*m), std::min(1.0, c[1]->L.*m), std::min(1.0, c[2]->L.*m),
                  std::min(1.0, c[3]->L.*m));
  };
  const double worst = std::max(std::max(ch(&Color::x), ch(&Color::y)), ch(&Color::z));
  return std::max(worst, spread(c[0]->alpha, c[1]->alpha, c[2]->alpha, c[3]->alpha));
}

}  // namespace

// One tile of the lattice: its points in `ws`, evaluated in camera batches through `eval`.
// Three stages, in order: corners(), refine(), resolve().
struct AdaptiveGrid::TileRun {
  TileRun(const AdaptiveGrid& g, int x0, int y0, int x1, int y1, AdaptiveWorkspace& ws,
          const EvalBatch& eval, uint64_t& rays, uint64_t& samples)
      : g(g),
        x0(x0),
        y0(y0),
        x1(x1),
        y1(y1),
        L(g.steps_),
        nx((x1 - x0) * L + 1),
        ny((y1 - y0) * L + 1),
        ws(ws),
        eval(eval),
        rays(rays),
        samples(samples),
        su(1.0 / (double(g.w_) * L)),
        sv(1.0 / (double(g.h_) * L)),
        row(uint64_t(g.w_) * L + 1) {
    if (ws.points.size() < size_t(nx) * ny) ws.points.resize(size_t(nx) * ny);
    if (++ws.tile == 0) {  // the counter wrapped: forget everything once
      std::fill(ws.points.begin(), ws.points.end(), AdaptiveWorkspace::Point{});
      ws.tile = 1, ws.stamp = 0;
    }
    tile = ws.tile;
  }

  const AdaptiveGrid& g;
  const int x0, y0, x1, y1, L, nx, ny;
  AdaptiveWorkspace& ws;
  const EvalBatch& eval;
  uint64_t &rays, &samples;
  const double su, sv;
  const uint64_t row;
  uint32_t tile = 0;
  // One camera batch.
  Vec2 uv[kCameraBatch];
  uint64_t keys[kCameraBatch];
  double fps[kCameraBatch];
  bool use[kCameraBatch];
  SampleResult out[kCameraBatch];
  CameraRayBatch cam;

  AdaptiveWorkspace::Point& at(int lx, int ly) const { return ws.points[size_t(ly) * nx + lx]; }
  int forced_depth(int x, int y) const {
    return int(ws.forced[size_t(y - y0) * (x1 - x0) + (x - x0)]);
  }
  void store(AdaptiveWorkspace::Point& p, const SampleResult& r) const {
    p.nan = !film_storable(r.L);
    p.L = p.nan ? Color{} : r.L;
    p.alpha = float(r.alpha);
    p.tile = tile;
    p.stamp = 0;  // counted by no pixel yet (stamps start at 1)
  }
  bool splits(int lx, int ly, int size, int forced) const {
    if (size <= 1) return false;
    if (forced > 0) return true;
    const AdaptiveWorkspace::Point* c[4] = {&at(lx, ly), &at(lx + size, ly), &at(lx, ly + size),
                                            &at(lx + size, ly + size)};
    return contrast(c) > g.threshold_;
  }
  // The coarsest level whose lattice holds a lattice coordinate (0 = pixel corners).
  int level_of(uint64_t c) const {
    int k = g.depth_;
    while (k > 0 && c % 2 == 0) c /= 2, --k;
    return k;
  }

  void corners();
  void refine();
  void evaluate_pending();
  void resolve(const Emit& emit);
};

// Pixel corners (cx, cy) in [x0, x1] x [y0, y1], in 4x4 blocks aligned to the image: camera
// batches and ray packets, and the same lanes in every tile that needs the block. Lanes of another
// tile's corners are masked off (a tile's last column and row of corners start a block of their
// own: without the mask a 32-pixel tile shaded 81 blocks, 1296 corners, for 1089). With the
// distortion map on, the corners' ray fields are kept for it.
void AdaptiveGrid::TileRun::corners() {
  if (g.distortion_) ws.corners.resize(size_t(x1 - x0 + 1) * (y1 - y0 + 1));
  for (int by = y0 / 4 * 4; by <= y1; by += 4)
    for (int bx = x0 / 4 * 4; bx <= x1; bx += 4) {
      for (int k = 0; k < kCameraBatch; ++k) {
        const int cx = bx + (k & 3), cy = by + (k >> 2);
        const uint64_t gx = uint64_t(cx) * L, gy = uint64_t(cy) * L;
        use[k] = cx <= g.w_ && cy <= g.h_ && cx >= x0 && cx <= x1 && cy >= y0 && cy <= y1;
        uv[k] = use[k] ? Vec2{gx * su, gy * sv} : Vec2{0.5, 0.5};
        keys[k] = mix64(gy * row + gx);
        fps[k] = 1;
        samples += use[k];
      }
      eval(uv, keys, fps, use, out, rays, g.distortion_ ? &cam : nullptr);
      for (int k = 0; k < kCameraBatch; ++k) {
        const int cx = bx + (k & 3), cy = by + (k >> 2);
        if (!use[k]) continue;
        store(at((cx - x0) * L, (cy - y0) * L), out[k]);
        if (g.distortion_)
          corner_geometry(cam, k, g.distance_, g.w_, g.h_,
                          &ws.corners[size_t(cy - y0) * (x1 - x0 + 1) + (cx - x0)]);
      }
    }
}

// Level by level: the squares that split ask for their edge midpoints and center; those are
// evaluated in batches before the next level looks at them. Whether each pixel splits at all is
// kept for resolve() (most pixels do not).
void AdaptiveGrid::TileRun::refine() {
  ws.level.clear();
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x)
      ws.level.push_back({(x - x0) * L, (y - y0) * L, L, forced_depth(x, y)});
  ws.pixel_splits.assign(ws.level.size(), 0);
  bool first = true;
  while (!ws.level.empty()) {
    ws.next_level.clear();
    ws.pending.clear();
    const auto request = [&](int lx, int ly) {
      AdaptiveWorkspace::Point& p = at(lx, ly);
      if (p.tile == tile) return;  // evaluated, or already asked for
      p.tile = tile;
      ws.pending.push_back(uint32_t(ly) * uint32_t(nx) + uint32_t(lx));
    };
    for (size_t qi = 0; qi < ws.level.size(); ++qi) {
      const AdaptiveWorkspace::Square& q = ws.level[qi];
      if (!splits(q.lx, q.ly, q.size, q.forced)) continue;
      if (first) ws.pixel_splits[qi] = 1;
      const int h = q.size / 2;
      request(q.lx + h, q.ly);
      request(q.lx, q.ly + h);
      request(q.lx + h, q.ly + h);
      request(q.lx + q.size, q.ly + h);
      request(q.lx + h, q.ly + q.size);
      for (int k = 0; k < 4; ++k)
        ws.next_level.push_back({q.lx + (k & 1) * h, q.ly + (k >> 1) * h, h, q.forced - 1});
    }
    evaluate_pending();
    ws.level.swap(ws.next_level);
    first = false;
  }
}

// The points one level asked for, in camera batches; each filters textures over the spacing of
// the coarsest level it belongs to.
void AdaptiveGrid::TileRun::evaluate_pending() {
  for (size_t b = 0; b < ws.pending.size(); b += kCameraBatch) {
    const int m = int(std::min<size_t>(kCameraBatch, ws.pending.size() - b));
    for (int k = 0; k < kCameraBatch; ++k) {
      use[k] = k < m;
      if (!use[k]) {
        uv[k] = {0.5, 0.5}, keys[k] = 0, fps[k] = 1;
        continue;
      }
      const uint32_t i = ws.pending[b + size_t(k)];
      const uint64_t gx = uint64_t(x0) * L + i % uint32_t(nx),
                     gy = uint64_t(y0) * L + i / uint32_t(nx);
      uv[k] = {gx * su, gy * sv};
      keys[k] = mix64(gy * row + gx);
      fps[k] = 1.0 / double(1 << std::max(level_of(gx), level_of(gy)));
    }
    eval(uv, keys, fps, use, out, rays, nullptr);
    for (int k = 0; k < m; ++k) store(ws.points[ws.pending[b + size_t(k)]], out[k]);
    samples += uint64_t(m);
  }
}

// Every point is known now: each pixel's mean over its squares, splitting as refine() did.
void AdaptiveGrid::TileRun::resolve(const Emit& emit) {
  uint32_t& stamp = ws.stamp;
  PixelResult acc;
  const auto point = [&](int lx, int ly) -> const AdaptiveWorkspace::Point& {
    AdaptiveWorkspace::Point& p = at(lx, ly);
    if (p.stamp != stamp) {
      p.stamp = stamp;
      acc.samples++;
      acc.nans += p.nan;
    }
    return p;
  };
  // Mean of a square of side `size` lattice steps; returns colour and alpha.
  // Recursive through its own parameter (a std::function cost ~6% of an adaptive render).
  // `split`: whether it splits, if known (-1: decide here).
  const auto square = [&](const auto& self, int lx, int ly, int size, int forced, int split,
                          Color& col, double& alpha) -> void {
    const AdaptiveWorkspace::Point* c[4] = {&point(lx, ly), &point(lx + size, ly),
                                            &point(lx, ly + size), &point(lx + size, ly + size)};
    if (split < 0 ? splits(lx, ly, size, forced) : split > 0) {
      const int h = size / 2;
      Color sum;
      double asum = 0;
      for (int k = 0; k < 4; ++k) {
        Color cc;
        double aa;
        self(self, lx + (k & 1) * h, ly + (k >> 1) * h, h, forced - 1, -1, cc, aa);
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
      square(square, (x - x0) * L, (y - y0) * L, L, forced_depth(x, y),
             ws.pixel_splits[size_t(y - y0) * (x1 - x0) + (x - x0)], premul, alpha);
      acc.alpha = alpha;
      acc.L = premul;  // the film's sums are coverage-weighted colour
      emit(x, y, acc);
    }
}

void AdaptiveGrid::render_tile(int x0, int y0, int x1, int y1, AdaptiveWorkspace& ws,
                               const EvalBatch& eval, const Emit& emit, uint64_t& rays,
                               uint64_t& samples) const {
  TileRun run(*this, x0, y0, x1, y1, ws, eval, rays, samples);
  run.corners();
  distortion_map(x0, y0, x1, y1, ws);
  run.refine();
  run.resolve(emit);
}

size_t update_active(const Film& film, const StopRule& rule, std::vector<uint8_t>* active) {
  const int W = film.width(), H = film.height();
  // n^-n_power for the sample counts a pixel can have, from std::pow once per count instead of
  // once per pixel (a pass over a 1080p film was a few percent of a whole Whitted render, serial).
  constexpr uint32_t kTable = 4096;
  double factor[kTable];
  for (uint32_t n = 0; n < kTable; ++n)
    factor[n] = std::pow(double(std::max(n, 1u)), -rule.n_power);
  // Each pixel's error estimate in units of its threshold; rows in parallel (inside the caller's
  // task arena), each pixel's value independent of the others, so any split gives the same mask.
  std::vector<double> excess(size_t(W) * H);
  parallel_chunks(0, size_t(H), 8, [&](size_t y0, size_t y1) {
    for (int y = int(y0); y < int(y1); ++y)
      for (int x = 0; x < W; ++x) {
        const double mean = luminance(film.pixel(x, y));
        const uint32_t n = film.samples(x, y);
        const double f = n < kTable ? factor[n] : std::pow(double(n), -rule.n_power);
        const double e = film.standard_error(x, y) * f;  // n^-0 is 1
        excess[size_t(y) * W + x] = e / (rule.threshold * std::sqrt(std::max(0.0, mean) + 1e-4));
      }
  });
  std::vector<uint32_t> row_count(size_t(H), 0);
  parallel_chunks(0, size_t(H), 8, [&](size_t y0, size_t y1) {
    for (int y = int(y0); y < int(y1); ++y)
      for (int x = 0; x < W; ++x) {
        uint8_t a = excess[size_t(y) * W + x] > 1;
        for (int dy = -1; dy <= 1 && !a; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int xx = x + dx, yy = y + dy;
            if (xx >= 0 && yy >= 0 && xx < W && yy < H &&
                excess[size_t(yy) * W + xx] > rule.neighbour_factor) {
              a = 1;
              break;
            }
          }
        (*active)[size_t(y) * W + x] = a;
        row_count[size_t(y)] += a;
      }
  });
  size_t n = 0;
  for (const uint32_t c : row_count) n += c;
  return n;
}

}  // namespace anamorph
