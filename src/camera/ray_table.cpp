#include "camera/ray_table.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace anamorph {

namespace {

// Catmull-Rom weights of the samples at -1, 0, 1, 2 for position t in [0, 1] between 0 and 1,
// and their first and second derivatives.
[[gnu::always_inline]] inline void catmull_rom(double t, double w[4], double dw[4], double ddw[4]) {
  const double t2 = t * t, t3 = t2 * t;
  w[0] = 0.5 * (-t + 2 * t2 - t3);
  w[1] = 0.5 * (2 - 5 * t2 + 3 * t3);
  w[2] = 0.5 * (t + 4 * t2 - 3 * t3);
  w[3] = 0.5 * (-t2 + t3);
  dw[0] = 0.5 * (-1 + 4 * t - 3 * t2);
  dw[1] = 0.5 * (-10 * t + 9 * t2);
  dw[2] = 0.5 * (1 + 8 * t - 9 * t2);
  dw[3] = 0.5 * (-2 * t + 3 * t2);
  ddw[0] = 2 - 3 * t;
  ddw[1] = -5 + 9 * t;
  ddw[2] = 4 - 9 * t;
  ddw[3] = -1 + 3 * t;
}

}  // namespace

RayTable::RayTable(const RayTableData& d) : w_(d.width), h_(d.height) {
  if (w_ < 1 || h_ < 1) throw std::invalid_argument("the table has no samples");
  const size_t n = size_t(w_) * size_t(h_);
  if (d.values.size() != n || (!d.valid.empty() && d.valid.size() != n))
    throw std::invalid_argument("the table's sample and validity counts do not match its size");
  stride_ = size_t(w_ + 2 * kPad);
  const size_t rows = size_t(h_ + 2 * kPad);
  grid_.assign(stride_ * rows, Vec3{});
  std::vector<char> known(stride_ * rows, 0);
  valid_.assign(n, 1);
  size_t count = 0;
  for (int j = 0; j < h_; ++j)
    for (int i = 0; i < w_; ++i) {
      const size_t k = size_t(j) * size_t(w_) + size_t(i);
      const bool ok = d.valid.empty() || d.valid[k];
      valid_[k] = ok ? 1 : 0;
      if (!ok) continue;
      const Vec3& x = d.values[k];
      if (!std::isfinite(x.x) || !std::isfinite(x.y) || !std::isfinite(x.z))
        throw std::invalid_argument("sample (" + std::to_string(i) + ", " + std::to_string(j) +
                                    ") is valid but not finite");
      const size_t g = size_t(j + kPad) * stride_ + size_t(i + kPad);
      grid_[g] = x, known[g] = 1, ++count;
    }
  if (count == 0) throw std::invalid_argument("the table has no valid sample");
  // Two rings of fill around the known samples (the reach of the stencil): each unknown sample
  // next to known ones takes the mean of the linear extrapolations 2 p(q+e) - p(q+2e) along the
  // 8 directions e where both are known, else the mean of its known neighbours.
  for (int ring = 0; ring < 2; ++ring) {
    std::vector<char> next = known;
    for (int j = 0; j < int(rows); ++j)
      for (int i = 0; i < int(stride_); ++i) {
        const size_t q = size_t(j) * stride_ + size_t(i);
        if (known[q]) continue;
        Vec3 extrapolated, neighbours;
        int ne = 0, nn = 0;
        for (int dj = -1; dj <= 1; ++dj)
          for (int di = -1; di <= 1; ++di) {
            if (!di && !dj) continue;
            const auto is_known = [&](int s) {
              const int x = i + s * di, y = j + s * dj;
              return x >= 0 && y >= 0 && x < int(stride_) && y < int(rows) &&
                     known[size_t(y) * stride_ + size_t(x)];
            };
            const auto p = [&](int s) {
              return grid_[size_t(j + s * dj) * stride_ + size_t(i + s * di)];
            };
            if (!is_known(1)) continue;
            neighbours += p(1), ++nn;
            if (is_known(2)) extrapolated += p(1) * 2.0 - p(2), ++ne;
          }
        if (nn == 0) continue;
        grid_[q] = ne ? extrapolated / double(ne) : neighbours / double(nn);
        next[q] = 1;
      }
    known = std::move(next);
  }
}

// The 4 x 4 Catmull-Rom stencil of cell (i, j) at (fs, ft) in it, separably: each row along u,
// then the rows along v.
template <bool kSecond>
void RayTable::interpolate(int i, int j, double fs, double ft, Vec3* value, Vec3* du, Vec3* dv,
                           Vec3* second) const {
  double wu[4], dwu[4], ddwu[4], wv[4], dwv[4], ddwv[4];
  catmull_rom(fs, wu, dwu, ddwu);
  catmull_rom(ft, wv, dwv, ddwv);
  Vec3 f, fu, fv, fuu, fuv, fvv;
  for (int b = 0; b < 4; ++b) {
    Vec3 row, drow, ddrow;
    for (int a = 0; a < 4; ++a) {
      const Vec3& p = at(i - 1 + a, j - 1 + b);
      row += p * wu[a];
      drow += p * dwu[a];
      if constexpr (kSecond) ddrow += p * ddwu[a];
    }
    f += row * wv[b];
    fu += drow * wv[b];
    fv += row * dwv[b];
    if constexpr (kSecond) {
      fuu += ddrow * wv[b];
      fuv += drow * dwv[b];
      fvv += row * ddwv[b];
    }
  }
  const double W = w_, H = h_;
  *value = f;
  *du = fu * W;
  *dv = fv * H;
  if constexpr (kSecond)
    second[0] = fuu * (W * W), second[1] = fuv * (W * H), second[2] = fvv * (H * H);
}

bool RayTable::eval(double u, double v, Vec3* value, Vec3* du, Vec3* dv, Vec3* second) const {
  const double s = u * w_ - 0.5, t = v * h_ - 0.5;
  if (!std::isfinite(s) || !std::isfinite(t)) return false;
  // The cell [i, i + 1] x [j, j + 1] holding (s, t), within the padded grid (beyond the outer
  // sample centers the last cell's cubic extends).
  const int i = std::clamp(int(std::floor(s)), -1, w_ - 1);
  const int j = std::clamp(int(std::floor(t)), -1, h_ - 1);
  // A ray where the bilinear interpolation of the 0/1 validity of the cell's corners (outside
  // the grid: the nearest edge sample's) reaches 1/2: at the samples it is their own validity,
  // and between valid and invalid samples the no-ray boundary runs halfway (a table resolves
  // its holes' outline to half a sample, no better).
  const auto ok = [&](int a, int b) {
    return valid_[size_t(std::clamp(b, 0, h_ - 1)) * size_t(w_) + size_t(std::clamp(a, 0, w_ - 1))]
               ? 1.0
               : 0.0;
  };
  const double fs0 = std::clamp(s - i, 0.0, 1.0), ft0 = std::clamp(t - j, 0.0, 1.0);
  const double m = (ok(i, j) * (1 - fs0) + ok(i + 1, j) * fs0) * (1 - ft0) +
                   (ok(i, j + 1) * (1 - fs0) + ok(i + 1, j + 1) * fs0) * ft0;
  if (!(m >= 0.5)) return false;
  if (second)
    interpolate<true>(i, j, s - i, t - j, value, du, dv, second);
  else
    interpolate<false>(i, j, s - i, t - j, value, du, dv, nullptr);
  return true;
}

}  // namespace anamorph
