#include "material/texture.h"

#include <algorithm>
#include <cmath>

namespace anamorph {

UvTransform UvTransform::from_offset_rotation_scale(Vec2 o, double r, Vec2 s) {
  // KHR_texture_transform: T * R * S with R rotating counter-clockwise in uv space.
  UvTransform t;
  const double c = std::cos(r), si = std::sin(r);
  t.m[0][0] = c * s.x;
  t.m[0][1] = si * s.y;
  t.m[0][2] = o.x;
  t.m[1][0] = -si * s.x;
  t.m[1][1] = c * s.y;
  t.m[1][2] = o.y;
  return t;
}

MipMap::MipMap(Image base) {
  levels_.push_back(std::move(base));
  // 2x2 box downsampling (odd sizes clamp the last row/column).
  while (levels_.back().width > 1 || levels_.back().height > 1) {
    const Image& src = levels_.back();
    Image dst;
    dst.width = std::max(1, src.width / 2);
    dst.height = std::max(1, src.height / 2);
    dst.channels = src.channels;
    dst.pixels.resize(size_t(dst.width) * dst.height * dst.channels);
    for (int y = 0; y < dst.height; ++y)
      for (int x = 0; x < dst.width; ++x)
        for (int c = 0; c < dst.channels; ++c) {
          const int x0 = std::min(2 * x, src.width - 1), x1 = std::min(2 * x + 1, src.width - 1);
          const int y0 = std::min(2 * y, src.height - 1), y1 = std::min(2 * y + 1, src.height - 1);
          dst.at(x, y, c) = 0.25f * (src.at(x0, y0, c) + src.at(x1, y0, c) + src.at(x0, y1, c) +
                                     src.at(x1, y1, c));
        }
    levels_.push_back(std::move(dst));
  }
}

static int wrap_index(int i, int n, Wrap w) {
  switch (w) {
    case Wrap::Clamp:
      return std::clamp(i, 0, n - 1);
    case Wrap::Mirror: {
      const int period = 2 * n;
      int m = ((i % period) + period) % period;
      return m < n ? m : period - 1 - m;
    }
    case Wrap::Repeat:
    default:
      return ((i % n) + n) % n;
  }
}

void MipMap::bilinear(int level, Vec2 uv, Wrap ws, Wrap wt, float out[4]) const {
  const Image& im = levels_[size_t(level)];
  const double x = uv.x * im.width - 0.5, y = uv.y * im.height - 0.5;
  const double fx = std::floor(x), fy = std::floor(y);
  const auto tx = float(x - fx), ty = float(y - fy);
  const int x0 = wrap_index(int(fx), im.width, ws), x1 = wrap_index(int(fx) + 1, im.width, ws);
  const int y0 = wrap_index(int(fy), im.height, wt), y1 = wrap_index(int(fy) + 1, im.height, wt);
  for (int c = 0; c < 4; ++c) {
    const int cc = std::min(c, im.channels - 1);
    const float a = im.at(x0, y0, cc) * (1 - tx) + im.at(x1, y0, cc) * tx;
    const float b = im.at(x0, y1, cc) * (1 - tx) + im.at(x1, y1, cc) * tx;
    out[c] = a * (1 - ty) + b * ty;
  }
  if (im.channels < 4) out[3] = 1;
}

void MipMap::lookup(Vec2 uv, double width, Wrap ws, Wrap wt, bool nearest, float out[4]) const {
  if (nearest) {
    const Image& im = levels_[0];
    const int x = wrap_index(int(std::floor(uv.x * im.width)), im.width, ws);
    const int y = wrap_index(int(std::floor(uv.y * im.height)), im.height, wt);
    for (int c = 0; c < 4; ++c) out[c] = im.at(x, y, std::min(c, im.channels - 1));
    if (im.channels < 4) out[3] = 1;
    return;
  }
  // Level where one texel matches the footprint width.
  const double texels = width * std::max(levels_[0].width, levels_[0].height);
  const double level = texels > 1 ? std::log2(texels) : 0.0;
  const int nlev = int(levels_.size());
  if (level >= nlev - 1) {
    bilinear(nlev - 1, uv, ws, wt, out);
    return;
  }
  const int l0 = int(level);
  const auto t = float(level - l0);
  bilinear(l0, uv, ws, wt, out);
  if (t > 0) {
    float o1[4];
    bilinear(l0 + 1, uv, ws, wt, o1);
    for (int c = 0; c < 4; ++c) out[c] = out[c] * (1 - t) + o1[c] * t;
  }
}

namespace {

// Integral of the square wave s(x) = +1 on [0,1), -1 on [1,2) (period 2): a triangle wave.
// (Branch-free: which half of the period x falls in is as good as random over a checkered
// floor, and the mispredicted branch was half of a texture lookup.)
double square_integral(double x) {
  const double t = x - 2 * std::floor(x * 0.5);
  return 1 - std::abs(t - 1);
}
// Box-filtered square wave over [x - w, x + w].
double filtered_square(double x, double w) {
  if (w < 1e-6) return (x - 2 * std::floor(x * 0.5)) < 1 ? 1.0 : -1.0;
  return (square_integral(x + w) - square_integral(x - w)) / (2 * w);
}
// Integral of the line indicator (1 within lw/2 of an integer).
double line_integral(double x, double lw) {
  const double s = x + lw * 0.5;
  const double f = std::floor(s);
  return f * lw + std::min(s - f, lw);
}
double filtered_line(double x, double w, double lw) {
  if (w < 1e-6) {
    const double s = x + lw * 0.5;
    return (s - std::floor(s)) < lw ? 1.0 : 0.0;
  }
  return std::clamp((line_integral(x + w, lw) - line_integral(x - w, lw)) / (2 * w), 0.0, 1.0);
}

}  // namespace

namespace {

// An image texture's value: its mip map looked up over the footprint, times the tint.
Color image_value(const Texture& t, const TexCoord& tc, double* alpha) {
  const Vec2 uv = t.uv_transform.apply(tc.uv);
  const Vec2 dx = t.uv_transform.apply_vector(tc.duvdx), dy = t.uv_transform.apply_vector(tc.duvdy);
  const double width = std::max({std::abs(dx.x), std::abs(dx.y), std::abs(dy.x), std::abs(dy.y)});
  float rgba[4];
  t.image->lookup(uv, width, t.wrap_s, t.wrap_t, t.nearest, rgba);
  if (alpha) *alpha = rgba[3];
  return Color{rgba[0], rgba[1], rgba[2]} * t.value;
}

// Where a procedural pattern is evaluated: coordinates, per-axis footprint half-widths, and the
// axes to use.
struct PatternPoint {
  Vec3 p, w;
  int axes[3] = {0, 1, 2};
  int naxes = 3;
};

PatternPoint pattern_point(const Texture& t, const TexCoord& tc) {
  PatternPoint q;
  const double inv_scale = 1 / t.scale;  // (one division, not nine)
  if (t.space == Texture::Space::Uv) {
    q.p = t.pattern_from_space.point({tc.uv.x, tc.uv.y, 0}) * inv_scale;
    const Vec3 dx = t.pattern_from_space.vector({tc.duvdx.x, tc.duvdx.y, 0}) * inv_scale;
    const Vec3 dy = t.pattern_from_space.vector({tc.duvdy.x, tc.duvdy.y, 0}) * inv_scale;
    for (int i = 0; i < 3; ++i) q.w[i] = 0.5 * (std::abs(dx[i]) + std::abs(dy[i]));
    q.naxes = 2;
    return q;
  }
  const bool obj = t.space == Texture::Space::Object;
  const Transform* ofw = obj ? tc.object_from_world : nullptr;
  const Vec3 ps = obj ? tc.p_object : tc.p_world;
  Vec3 dx = tc.dpdx, dy = tc.dpdy, n = obj ? tc.n_object : tc.n_world;
  if (ofw) dx = ofw->vector(dx), dy = ofw->vector(dy);
  q.p = t.pattern_from_space.point(ps) * inv_scale;
  dx = t.pattern_from_space.vector(dx) * inv_scale;
  dy = t.pattern_from_space.vector(dy) * inv_scale;
  n = t.pattern_from_space.normal(n);
  for (int i = 0; i < 3; ++i) q.w[i] = 0.5 * (std::abs(dx[i]) + std::abs(dy[i]));
  // Drop the axis along the normal: on a floor y = 0 the pattern must not depend on y,
  // whose value sits exactly on a cell boundary.
  int drop = 0;
  const Vec3 an{std::abs(n.x), std::abs(n.y), std::abs(n.z)};
  if (an.y > an[drop]) drop = 1;
  if (an.z > an[drop]) drop = 2;
  if (an.x > 0 || an.y > 0 || an.z > 0) {
    q.naxes = 0;
    for (int i = 0; i < 3; ++i)
      if (i != drop) q.axes[q.naxes++] = i;
  }
  return q;
}

}  // namespace

Color Texture::eval(const TexCoord& tc, double* alpha) const {
  if (alpha) *alpha = 1;
  switch (kind) {
    case Kind::Constant:
      return value;
    case Kind::Image:
      return image_value(*this, tc, alpha);
    case Kind::Checker:
    case Kind::Grid:
      break;
  }
  const PatternPoint q = pattern_point(*this, tc);
  if (kind == Kind::Checker) {
    double f = 1;
    for (int k = 0; k < q.naxes; ++k) f *= filtered_square(q.p[q.axes[k]], q.w[q.axes[k]]);
    return color_a * (0.5 * (1 + f)) + color_b * (0.5 * (1 - f));
  }
  double none = 1;  // probability of being off every line
  for (int k = 0; k < q.naxes; ++k)
    none *= 1 - filtered_line(q.p[q.axes[k]], q.w[q.axes[k]], line_width);
  return color_a * none + color_b * (1 - none);
}

}  // namespace anamorph
