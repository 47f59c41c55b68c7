#include "io/mip_texture.h"

#include <algorithm>
#include <cmath>

#include "math/parallel.h"

namespace anamorph {

namespace {

// At most this many probes along an axis: a longer footprint goes to a coarser level.
constexpr int kMaxProbes = 16;
// The level's texels are this many octaves finer than the footprint's minor axis (a quarter of
// it), so that the probes' grid, not the pyramid's box, shapes the filter. Measured by warping a
// 512 x 256 equirect to 64 x 64 fisheye and Panini targets (2-4 source pixels a target pixel)
// against their direct 1024-spp renders, mean |difference|: 0.0105 / 0.0121 at 0 octaves (plain
// trilinear), 0.0036 / 0.0040 at 1, 0.0022 / 0.0032 at 2 and 3 (OpenImageIO's aniso: 0.0046 /
// 0.0060).
constexpr double kFinerLevels = 2;

}  // namespace

std::vector<float> rgba_pixels(Image&& image) {
  const int c = image.channels;
  if (c == 4) return std::move(image.pixels);
  const size_t n = size_t(image.width) * size_t(image.height);
  std::vector<float> out(n * 4);
  for (size_t i = 0; i < n; ++i) {
    const float* p = &image.pixels[i * size_t(c)];
    const bool grey = c < 3;
    for (int k = 0; k < 3; ++k) out[i * 4 + size_t(k)] = grey ? p[0] : p[k];
    out[i * 4 + 3] = c == 2 ? p[1] : 1.0f;
  }
  return out;
}

MipTexture::MipTexture(Image image, bool wrap_u) : wrap_u_(wrap_u) {
  Level base;
  base.width = image.width, base.height = image.height;
  base.rgba = rgba_pixels(std::move(image));
  levels_.push_back(std::move(base));
  while (levels_.back().width > 1 || levels_.back().height > 1) {
    const Level& f = levels_.back();
    Level c;
    c.width = std::max(1, (f.width + 1) / 2), c.height = std::max(1, (f.height + 1) / 2);
    c.rgba.resize(size_t(c.width) * size_t(c.height) * 4);
    // A 2x2 box; an odd size's last texel repeats (or wraps around u).
    parallel_for_each(0, c.height, [&](int y) {
      const int y0 = std::min(2 * y, f.height - 1), y1 = std::min(2 * y + 1, f.height - 1);
      for (int x = 0; x < c.width; ++x) {
        const int x0 = std::min(2 * x, f.width - 1);
        const int x1 = 2 * x + 1 < f.width ? 2 * x + 1 : wrap_u_ ? 0 : f.width - 1;
        for (int k = 0; k < 4; ++k) {
          const auto at = [&](int xx, int yy) {
            return f.rgba[(size_t(yy) * size_t(f.width) + size_t(xx)) * 4 + size_t(k)];
          };
          c.rgba[(size_t(y) * size_t(c.width) + size_t(x)) * 4 + size_t(k)] =
              0.25f * ((at(x0, y0) + at(x1, y0)) + (at(x0, y1) + at(x1, y1)));
        }
      }
    });
    levels_.push_back(std::move(c));
  }
}

void MipTexture::add_bilinear(const Level& l, double u, double v, float weight,
                              float sum[4]) const {
  const double px = u * l.width - 0.5, py = v * l.height - 0.5;
  if (!(std::abs(px) < 1e9 && std::abs(py) < 1e9)) return;  // (NaN too)
  const double fx0 = std::floor(px), fy0 = std::floor(py);
  const float fx = float(px - fx0), fy = float(py - fy0);
  const long w = l.width, h = l.height;
  long x0 = long(fx0), y0 = long(fy0), x1 = x0 + 1, y1 = y0 + 1;
  float wx0 = 1 - fx, wx1 = fx, wy0 = 1 - fy, wy1 = fy;
  if (wrap_u_) {
    if (x0 < 0 || x0 >= w) x0 = ((x0 % w) + w) % w;
    x1 = x0 + 1 == w ? 0 : x0 + 1;
    y0 = std::clamp(y0, 0L, h - 1), y1 = std::clamp(y1, 0L, h - 1);
  } else {  // (a texel outside weighs 0; its index is moved inside)
    const auto outside = [](long& i, long n, float& wi) {
      if (i >= 0 && i < n) return;
      i = 0, wi = 0;
    };
    outside(x0, w, wx0), outside(x1, w, wx1), outside(y0, h, wy0), outside(y1, h, wy1);
  }
  const float* r0 = &l.rgba[size_t(y0) * size_t(w) * 4];
  const float* r1 = &l.rgba[size_t(y1) * size_t(w) * 4];
  const float *a = r0 + x0 * 4, *b = r0 + x1 * 4, *c = r1 + x0 * 4, *d = r1 + x1 * 4;
  for (int k = 0; k < 4; ++k)
    sum[k] += weight * (wy0 * (wx0 * a[k] + wx1 * b[k]) + wy1 * (wx0 * c[k] + wx1 * d[k]));
}

void MipTexture::bilinear(Vec2 uv, float rgba[4]) const {
  std::fill(rgba, rgba + 4, 0.0f);
  add_bilinear(levels_[0], uv.x, uv.y, 1.0f, rgba);
}

void MipTexture::add_probes(int li, Vec2 uv, const Footprint& f, float weight, float sum[4]) const {
  const double texel = std::ldexp(1.0, li);  // (level-0 pixels)
  const auto count = [&](double span) {
    return span > 0 ? std::min(int(std::ceil(span / texel)) + 1, kMaxProbes) : 1;
  };
  const double span1 = std::max(f.major - texel, 0.0), span2 = std::max(f.minor - texel, 0.0);
  const int n1 = count(span1), n2 = count(span2);
  const Vec2 minor_axis{-f.axis.y, f.axis.x};
  const double W = width(), H = height();
  const float w = weight / float(n1 * n2);
  for (int j = 0; j < n2; ++j) {
    const double b = n2 > 1 ? span2 * (double(j) / (n2 - 1) - 0.5) : 0.0;
    for (int i = 0; i < n1; ++i) {
      const double a = n1 > 1 ? span1 * (double(i) / (n1 - 1) - 0.5) : 0.0;
      const Vec2 at = f.axis * a + minor_axis * b;
      add_bilinear(levels_[size_t(li)], uv.x + at.x / W, uv.y + at.y / H, w, sum);
    }
  }
}

void MipTexture::area(Vec2 uv, Vec2 duv_dx, Vec2 duv_dy, float rgba[4]) const {
  // The footprint in level-0 pixels: the singular values (major, minor) of the Jacobian
  // [dx dy] and the major one's direction.
  const double W = width(), H = height();
  const double ax = duv_dx.x * W, ay = duv_dx.y * H, bx = duv_dy.x * W, by = duv_dy.y * H;
  const double p = ax * ax + bx * bx, q = ay * ay + by * by, r = ax * ay + bx * by;
  const double mean = 0.5 * (p + q), d = std::sqrt(0.25 * (p - q) * (p - q) + r * r);
  const double major = std::sqrt(mean + d), minor = std::sqrt(std::max(mean - d, 0.0));
  if (!(major > 1) || !std::isfinite(major)) return bilinear(uv, rgba);
  Vec2 axis{r, mean + d - p};
  const Vec2 other{mean + d - q, r};
  if (other.x * other.x + other.y * other.y > axis.x * axis.x + axis.y * axis.y) axis = other;
  const double norm = std::sqrt(axis.x * axis.x + axis.y * axis.y);
  axis = norm > 0 ? axis / norm : Vec2{1, 0};
  const Footprint f{major, minor, axis};
  // (level 0 without a logarithm in the common case)
  double lod = 0;
  if (minor > std::exp2(kFinerLevels) || major > kMaxProbes)
    lod = std::clamp(
        std::max(std::log2(std::max(minor, 1.0)) - kFinerLevels, std::log2(major / kMaxProbes)),
        0.0, double(levels() - 1));
  const int lo = int(std::floor(lod));
  const float t = float(lod - lo);
  std::fill(rgba, rgba + 4, 0.0f);
  add_probes(lo, uv, f, 1 - t, rgba);
  if (t > 0 && lo + 1 < levels()) add_probes(lo + 1, uv, f, t, rgba);
}

}  // namespace anamorph
