// camera_coin_gallery: the plots and pictures of docs/coins.md, made from the coin code itself.
//   camera_coin_gallery <dir>   writes <dir>/coin_*.png
// Plots are drawn here (no plotting library needed): curves on a grid with numeric tick labels;
// what each curve is, is said in the captions of docs/coins.md. The magnification plot also
// carries dots measured on a real camera, so it checks the formula it illustrates.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include "camera/coins.h"
#include "camera/presets.h"
#include "io/image_io.h"
#include "render/renderer.h"
#include "scene/scene_loader.h"

namespace anamorph {
namespace {

namespace fs = std::filesystem;

// ---- a tiny plotter ---------------------------------------------------------------------------

// 3x5 glyphs for tick labels.
const char* glyph(char c) {
  switch (c) {
    case '0':
      return "111101101101111";
    case '1':
      return "010110010010111";
    case '2':
      return "111001111100111";
    case '3':
      return "111001111001111";
    case '4':
      return "101101111001001";
    case '5':
      return "111100111001111";
    case '6':
      return "111100111101111";
    case '7':
      return "111001001001001";
    case '8':
      return "111101111101111";
    case '9':
      return "111101111001111";
    case '.':
      return "000000000000010";
    case '-':
      return "000000111000000";
    case '/':
      return "001001010100100";
    default:
      return "000000000000000";
  }
}

struct Rgb {
  double r, g, b;  // sRGB in [0, 1]
};

class Plot {
 public:
  Plot(int w, int h, double x0, double x1, double y0, double y1, bool log2_y = false)
      : w_(w),
        h_(h),
        x0_(x0),
        x1_(x1),
        y0_(y0),
        y1_(y1),
        log_(log2_y),
        px_(size_t(w) * h * 3, 1.0) {}

  // Grid lines at the given values, labelled along the axes.
  void grid(const std::vector<double>& xs, const std::vector<double>& ys,
            const std::vector<std::string>& xl, const std::vector<std::string>& yl) {
    for (size_t i = 0; i < xs.size(); ++i) {
      line({xs[i], ymin()}, {xs[i], ymax()}, {0.85, 0.85, 0.85}, 1.0);
      text(sx(xs[i]) - 3.0 * xl[i].size(), h_ - kMargin + 8, xl[i]);
    }
    for (size_t i = 0; i < ys.size(); ++i) {
      line({x0_, ys[i]}, {x1_, ys[i]}, {0.85, 0.85, 0.85}, 1.0);
      text(kMargin - 10 - 8.0 * yl[i].size(), sy(ys[i]) - 5, yl[i]);
    }
    // Axes.
    line({x0_, ymin()}, {x1_, ymin()}, {0.2, 0.2, 0.2}, 1.2);
    line({x0_, ymin()}, {x0_, ymax()}, {0.2, 0.2, 0.2}, 1.2);
  }

  void curve(const std::function<double(double)>& f, Rgb c, double width = 2.2,
             bool dashed = false) {
    const int n = 1200;
    for (int i = 0; i < n; ++i) {
      if (dashed && (i / 20) % 2) continue;
      const double a = x0_ + (x1_ - x0_) * i / n, b = x0_ + (x1_ - x0_) * (i + 1) / n;
      const double fa = f(a), fb = f(b);
      if (std::isfinite(fa) && std::isfinite(fb)) line({a, fa}, {b, fb}, c, width);
    }
  }

  void marker(double x, double y, Rgb c, double radius = 4) {
    const double cx = sx(x), cy = sy(y);
    for (int j = int(cy - radius - 2); j <= int(cy + radius + 2); ++j)
      for (int i = int(cx - radius - 2); i <= int(cx + radius + 2); ++i) {
        const double d = std::hypot(i + 0.5 - cx, j + 0.5 - cy);
        blend(i, j, c, std::clamp(radius + 0.5 - d, 0.0, 1.0));
      }
  }

  void write(const fs::path& file) const { write_rgb(file, w_, h_, px_); }

  static void write_rgb(const fs::path& file, int w, int h, const std::vector<double>& srgb) {
    OutputImage img;
    img.width = w;
    img.height = h;
    ImageLayer l;
    l.channels = {"R", "G", "B", "A"};
    for (size_t i = 0; i < size_t(w) * h; ++i) {
      for (int c = 0; c < 3; ++c) l.data.push_back(srgb_to_linear(float(srgb[i * 3 + c])));
      l.data.push_back(1.0f);
    }
    img.layers.push_back(std::move(l));
    img.metadata["anamorph.generator"] = "camera_coin_gallery (tests/camera/coin_gallery.cpp)";
    write_png(file, img);
    std::cout << "wrote " << file.string() << "\n";
  }

 private:
  static constexpr int kMargin = 56;
  double ymin() const { return y0_; }
  double ymax() const { return y1_; }
  double ty(double y) const { return log_ ? std::log2(y) : y; }
  double sx(double x) const { return kMargin + (x - x0_) / (x1_ - x0_) * (w_ - kMargin - 16); }
  double sy(double y) const {
    return (h_ - kMargin) - (ty(y) - ty(y0_)) / (ty(y1_) - ty(y0_)) * (h_ - kMargin - 16);
  }
  void blend(int i, int j, Rgb c, double a) {
    if (i < 0 || j < 0 || i >= w_ || j >= h_ || a <= 0) return;
    double* p = &px_[(size_t(j) * w_ + i) * 3];
    p[0] += (c.r - p[0]) * a;
    p[1] += (c.g - p[1]) * a;
    p[2] += (c.b - p[2]) * a;
  }
  // Antialiased segment between data points, clipped to the plot area.
  void line(Vec2 a, Vec2 b, Rgb c, double width) {
    const Vec2 p{sx(a.x), sy(a.y)}, q{sx(b.x), sy(b.y)};
    const double top = 16, bottom = h_ - kMargin;
    const int i0 = int(std::floor(std::min(p.x, q.x) - width)),
              i1 = int(std::ceil(std::max(p.x, q.x) + width));
    const int j0 = int(std::floor(std::max(top, std::min(p.y, q.y) - width))),
              j1 = int(std::ceil(std::min(bottom, std::max(p.y, q.y) + width)));
    const Vec2 e = q - p;
    const double ee = anamorph::dot(e, e);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const Vec2 x{i + 0.5, j + 0.5};
        const double t = ee > 0 ? std::clamp(anamorph::dot(x - p, e) / ee, 0.0, 1.0) : 0;
        const double d = length(x - (p + e * t));
        blend(i, j, c, std::clamp(width / 2 + 0.5 - d, 0.0, 1.0));
      }
  }
  void text(double x, double y, const std::string& s) {
    for (size_t k = 0; k < s.size(); ++k) {
      const char* g = glyph(s[k]);
      for (int r = 0; r < 5; ++r)
        for (int c = 0; c < 3; ++c)
          if (g[r * 3 + c] == '1')
            for (int dy = 0; dy < 2; ++dy)
              for (int dx = 0; dx < 2; ++dx)
                blend(int(x) + int(k) * 8 + c * 2 + dx, int(y) + r * 2 + dy, {0.25, 0.25, 0.25}, 1);
    }
  }

  int w_, h_;
  double x0_, x1_, y0_, y1_;
  bool log_;
  std::vector<double> px_;
};

const Rgb kBlue{0.12, 0.32, 0.7}, kOrange{0.93, 0.5, 0.1}, kGreen{0.15, 0.6, 0.25},
    kGrey{0.5, 0.5, 0.5}, kRed{0.8, 0.12, 0.1};

// Shades from dark to light of one hue.
Rgb shade(Rgb c, double t) {
  return {c.r + (1 - c.r) * t, c.g + (1 - c.g) * t, c.b + (1 - c.b) * t};
}

void plot_weights(const fs::path& dir) {
  const std::vector<double> xt{0, 0.25, 0.5, 0.75, 1, 1.2}, yt{0, 0.25, 0.5, 0.75, 1};
  const std::vector<std::string> xl{"0", ".25", ".5", ".75", "1", "1.2"},
      yl{"0", ".25", ".5", ".75", "1"};
  {
    Plot p(640, 400, 0, 1.2, 0, 1.05);
    p.grid(xt, yt, xl, yl);
    const CoinFalloff fs[] = {CoinFalloff::Smooth, CoinFalloff::Quadratic, CoinFalloff::Gaussian};
    const Rgb cs[] = {kBlue, kOrange, kGreen};
    for (int i = 0; i < 3; ++i)
      p.curve([&](double t) { return coin_weight(1, 1, t, 1, 1, 1, fs[i]); }, cs[i]);
    p.write(dir / "coin_falloff.png");
  }
  {
    Plot p(640, 400, 0, 1.2, 0, 1.05);
    p.grid(xt, yt, xl, yl);
    const double ss[] = {0.1, 0.3, 1, 3, 10};
    for (int i = 0; i < 5; ++i)
      p.curve([&](double t) { return coin_weight(1, 1, t, ss[i], 1, 1); }, shade(kBlue, 0.15 * i));
    p.write(dir / "coin_stiffness.png");
  }
  {
    Plot p(640, 400, 0, 4, 0, 1.05);
    p.grid({0, 0.5, 1, 2, 3, 4}, yt, {"0", ".5", "1", "2", "3", "4"}, yl);
    p.curve([](double l) { return coin_weight(1, l, 0, 1, 1, 1); }, kBlue);
    p.curve([](double l) { return 2 / (l * l); }, kGrey, 1.5, true);
    p.curve([](double l) { return 2 * l * l; }, kGrey, 1.5, true);
    p.write(dir / "coin_distance.png");
  }
}

// Area magnification of the radial model (a pinhole): r -> (1 - w(r)) r scales lengths by
// 1 / (1 - w) across the radius and 1 / (1 - w - r w') along it.
double model_magnification(double m, double s, double t) {
  const double h = 1e-6;
  const auto w = [&](double x) { return coin_weight(m, 1, std::abs(x), s, 1, 1); };
  const double wr = (w(t + h) - w(t - h)) / (2 * h);
  return 1 / ((1 - w(t)) * (1 - w(t) - t * wr));
}

// Footprint area, on the plane through `p` facing the camera, of the ray field's derivatives.
double footprint(const CameraRay& r, const Vec3& p, const Vec3& n) {
  const double t = dot(p - r.org, n) / dot(r.dir, n);
  const auto dX = [&](const Vec3& dorg, const Vec3& ddir) {
    const double dt = -(dot(dorg, n) + t * dot(ddir, n)) / dot(r.dir, n);
    return dorg + ddir * t + r.dir * dt;
  };
  return length(cross(dX(r.dorg_du, r.ddir_du), dX(r.dorg_dv, r.ddir_dv)));
}

void plot_magnification(const fs::path& dir) {
  Plot p(640, 400, 0, 1.2, 0.25, 16, true);
  p.grid({0, 0.25, 0.5, 0.75, 1, 1.2}, {0.25, 0.5, 1, 2, 4, 8, 16},
         {"0", ".25", ".5", ".75", "1", "1.2"}, {".25", ".5", "1", "2", "4", "8", "16"});
  const double ms[] = {0.75, 0.5, 0.25, -0.5};
  const Rgb cs[] = {kRed, shade(kRed, 0.3), shade(kRed, 0.55), kBlue};
  // Measured: a narrow perspective camera with an org coin of radius 0.3, sampled along +u.
  const std::string rig = "look_from = [0, 0, 0]\nlook_at = [0, 0, -1]\nup = [0, 1, 0]\nfov = 20";
  const Vec3 coin{0, 0, -5}, n{0, 0, 1};
  const VirtualCamera plain(make_preset("perspective", rig, {400, 400}));
  for (int i = 0; i < 4; ++i) {
    p.curve([&](double t) { return model_magnification(ms[i], 1, t); }, cs[i]);
    VirtualCameraParts parts = make_preset("perspective", rig, {400, 400});
    Coin c;
    c.position = coin;
    c.strength = ms[i];
    c.radius = 0.3;
    c.affects = CoinAffects::Org;
    parts.coins = {c};
    const VirtualCamera cam(std::move(parts));
    for (double t = 0; t <= 1.15; t += 0.1) {
      const Vec2 uv{0.5 + 0.3 * t, 0.5};
      const auto r0 = plain.generate({uv}), r1 = cam.generate({uv});
      p.marker(t, footprint(*r0, coin, n) / footprint(*r1, coin, n), cs[i]);
    }
  }
  p.write(dir / "coin_magnification.png");
}

// The paper's setting through the renderer: a checkered floor with spheres, the coin on one.
const char* kScene = R"(
[image]
width = 320
height = 240
[render]
integrator = "whitted"
spp = 4
[camera]
look_from = [0, 2.2, 6]
look_at = [0, 0, 0]
fov = 55
[[camera.coin]]
position = [0.9, 0, 0.4]
strength = 0
radius = 0.22
[[material]]
name = "floor"
color = { type = "checker", space = "world", scale = 0.5, color_a = [0.9, 0.9, 0.86], color_b = [0.08, 0.08, 0.1] }
[[material]]
name = "grid"
color = { type = "grid", space = "uv", scale = 0.125, line_width = 0.12, color_a = [0.95, 0.75, 0.3], color_b = [0.2, 0.1, 0.05] }
[[material]]
name = "blue"
color = [0.2, 0.35, 0.8]
specular = 0.3
exponent = 60
[[object]]
type = "disk"
center = [0, -0.5, 0]
normal = [0, 1, 0]
radius = 8
material = "floor"
[[object]]
type = "sphere"
center = [0.9, 0, 0.4]
radius = 0.5
material = "grid"
[[object]]
type = "sphere"
center = [-1.1, 0, -0.6]
radius = 0.5
material = "blue"
[[object]]
type = "sphere"
center = [-0.2, -0.2, 1.6]
radius = 0.3
material = "blue"
[[light]]
type = "point"
position = [3, 6, 5]
intensity = 60
[environment]
color = [0.55, 0.65, 0.8]
)";

void render_panels(const fs::path& dir) {
  struct Panel {
    const char* file;
    std::vector<std::string> set;
    bool overlay;
  };
  const Panel panels[] = {
      {"coin_render_none.png", {}, false},
      {"coin_render_org.png", {"camera.coin.0.strength=0.6", "camera.coin.0.affects=org"}, false},
      {"coin_render_dir.png", {"camera.coin.0.strength=0.6", "camera.coin.0.affects=dir"}, false},
      {"coin_render_both.png", {"camera.coin.0.strength=0.6", "camera.coin.0.affects=both"}, false},
      {"coin_render_soft.png",
       {"camera.coin.0.strength=0.6", "camera.coin.0.stiffness=0.15", "camera.coin.0.radius=0.4"},
       false},
      {"coin_render_overlay.png", {"camera.coin.0.strength=0.6"}, true},
  };
  for (const Panel& pn : panels) {
    const Scene s = load_scene_from_string(kScene, "coins.toml", pn.set);
    const Renderer renderer(s);
    Film film(s.render.width, s.render.height, {});
    RenderOptions opt;
    renderer.render(film, opt);
    const int w = film.width(), h = film.height();
    std::vector<double> px(size_t(w) * h * 3);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const Color c = film.pixel(x, y);
        double cov =
            pn.overlay ? coin_overlay(*s.camera, {(x + 0.5) / w, (y + 0.5) / h}, {1.0 / w, 1.0 / h})
                       : 0;
        for (int k = 0; k < 3; ++k) {
          const double v = linear_to_srgb(float(std::clamp(c[k], 0.0, 1.0)));
          const double mark = k == 0 ? 1.0 : 0.1;
          px[(size_t(y) * w + x) * 3 + k] = v + (mark - v) * cov;
        }
      }
    Plot::write_rgb(dir / pn.file, w, h, px);
  }
}

}  // namespace
}  // namespace anamorph

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: camera_coin_gallery <output dir>   (docs/images/coins)\n";
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  std::filesystem::create_directories(dir);
  anamorph::plot_weights(dir);
  anamorph::plot_magnification(dir);
  anamorph::render_panels(dir);
  return 0;
}
