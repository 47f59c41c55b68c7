// camera_preset_gallery: the pictures and parameter tables of docs/cameras.md, made from the
// presets themselves.
//   camera_preset_gallery images <dir>     renders every preset's picture into <dir>/<name>.png
//   camera_preset_gallery tables <file.md> rewrites the blocks between "<!-- params:NAME -->"
//                                          and "<!-- /params:NAME -->" with the current tables
// The pictures show a small analytic scene (ground checkerboard, a sky with a 30/15-degree
// longitude/latitude grid, colored spheres at the four compass points and overhead, posts and
// near spheres for parallax), ray traced directly so they depend on nothing but the cameras.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "camera/presets.h"
#include "io/image_io.h"

namespace anamorph {
namespace {

struct Sphere {
  Vec3 c;
  double r;
  Color color;
};
struct Post {  // vertical cylinder from the ground to y = top
  double x, z, r, top;
  Color color;
};

const Sphere kSpheres[] = {
    {{0, 0, -5}, 1, {0.8, 0.1, 0.08}},           // front: red
    {{5, 0, 0}, 1, {0.1, 0.6, 0.1}},             // right: green
    {{0, 0, 5}, 1, {0.1, 0.2, 0.8}},             // back: blue
    {{-5, 0, 0}, 1, {0.85, 0.7, 0.05}},          // left: yellow
    {{0, 5, 0}, 1, {0.9, 0.9, 0.9}},             // overhead: white
    {{1.2, -0.6, -2.5}, 0.4, {0.7, 0.1, 0.7}},   // near, front right: magenta
    {{-1.5, -0.3, -3.2}, 0.5, {0.1, 0.7, 0.7}},  // near, front left: cyan
};
const Post kPosts[] = {
    {2.5, -4, 0.15, 2.5, {0.9, 0.5, 0.2}},
    {-2.5, -4, 0.15, 2.5, {0.9, 0.5, 0.2}},
    {2.5, 4, 0.15, 2.5, {0.5, 0.5, 0.5}},
    {-2.5, 4, 0.15, 2.5, {0.5, 0.5, 0.5}},
};
constexpr double kGround = -1.2;
const Vec3 kSun = normalize(Vec3{0.4, 0.8, 0.3});

struct Hit {
  double t = kInf;
  Vec3 n;
  Color albedo;
};

void hit_sphere(const Sphere& s, const Vec3& o, const Vec3& d, Hit* h) {
  const Vec3 oc = o - s.c;
  const double b = dot(oc, d), c = dot(oc, oc) - s.r * s.r, disc = b * b - c;
  if (disc < 0) return;
  const double sq = std::sqrt(disc);
  for (double t : {-b - sq, -b + sq})
    if (t > 1e-9 && t < h->t) {
      h->t = t;
      h->n = (o + d * t - s.c) / s.r;
      h->albedo = s.color;
      return;
    }
}

void hit_post(const Post& p, const Vec3& o, const Vec3& d, Hit* h) {
  const double ox = o.x - p.x, oz = o.z - p.z;
  const double a = d.x * d.x + d.z * d.z, b = ox * d.x + oz * d.z,
               c = ox * ox + oz * oz - p.r * p.r;
  if (a <= 0) return;
  const double disc = b * b - a * c;
  if (disc < 0) return;
  const double t = (-b - std::sqrt(disc)) / a;
  if (!(t > 1e-9 && t < h->t)) return;
  const double y = o.y + d.y * t;
  if (y < kGround || y > p.top) return;
  h->t = t;
  h->n = normalize(Vec3{ox + d.x * t, 0, oz + d.z * t});
  h->albedo = p.color;
}

Hit trace(const Vec3& o, const Vec3& d) {
  Hit h;
  for (const auto& s : kSpheres) hit_sphere(s, o, d, &h);
  for (const auto& p : kPosts) hit_post(p, o, d, &h);
  if (d.y < 0) {
    const double t = (kGround - o.y) / d.y;
    if (t > 1e-9 && t < h.t) {
      const Vec3 p = o + d * t;
      const bool odd = (int(std::floor(p.x)) + int(std::floor(p.z))) & 1;
      h.t = t;
      h.n = {0, 1, 0};
      h.albedo = odd ? Color{0.75, 0.75, 0.72} : Color{0.25, 0.27, 0.3};
    }
  }
  return h;
}

Color sky(const Vec3& d) {
  const double lat = std::asin(std::clamp(d.y, -1.0, 1.0)), lon = std::atan2(d.x, -d.z);
  Color c = lerp(std::max(d.y, 0.0), Color{0.75, 0.85, 0.95}, Color{0.25, 0.45, 0.85});
  // Grid lines every 30 degrees of longitude and 15 of latitude, 0.5 degrees wide.
  const double w = radians(0.5);
  const double mlon = std::remainder(lon, radians(30)) * std::cos(lat);
  const double mlat = std::remainder(lat, radians(15));
  if (std::abs(mlon) < w || std::abs(mlat) < w) c = c * 0.6;
  if (std::abs(lon) < w && d.y > 0) c = Color{1, 0.3, 0.2};  // longitude 0 (straight ahead)
  return c;
}

Color shade(const Vec3& o, const Vec3& d) {
  const Hit h = trace(o, d);
  if (h.t == kInf) return sky(d);
  const Vec3 p = o + d * h.t;
  const bool lit = trace(p + h.n * 1e-6, kSun).t == kInf;
  const double diffuse = lit ? std::max(0.0, dot(h.n, kSun)) : 0;
  Color c = h.albedo * (0.25 + 0.75 * diffuse);
  // A little haze so the checkerboard does not alias at the horizon.
  const double fog = 1 - std::exp(-h.t / 40);
  return lerp(fog, c, Color{0.75, 0.85, 0.95});
}

OutputImage render(const Camera& cam, int w, int h) {
  OutputImage img;
  img.width = w, img.height = h;
  ImageLayer beauty;
  beauty.channels = {"R", "G", "B", "A"};
  beauty.data.resize(size_t(w) * h * 4);
  const int n = 3;  // n x n samples per pixel
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      Color sum;
      double alpha = 0;
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          CameraSample s;
          s.uv = {(x + (i + 0.5) / n) / w, (y + (j + 0.5) / n) / h};
          const auto r = cam.generate(s);
          if (!r) continue;  // no ray: transparent
          sum += shade(r->org, r->dir);
          alpha += 1;
        }
      float* px = &beauty.data[(size_t(y) * w + x) * 4];
      const Color c = alpha > 0 ? sum / alpha : Color{};
      px[0] = float(c.x), px[1] = float(c.y), px[2] = float(c.z), px[3] = float(alpha / (n * n));
    }
  img.layers.push_back(std::move(beauty));
  return img;
}

struct Shot {
  const char* preset;
  const char* toml;
  int w, h;
};

// Eye height 0, looking along -z unless a shot says otherwise.
const Shot kShots[] = {
    {"perspective", "fov = 90", 480, 270},
    {"orthographic", "look_from = [0, 6, 6]\nlook_at = [0, -1, -2]\nview_width = 14", 480, 270},
    {"fisheye", "fov = 180", 320, 320},
    {"mirror_ball", "", 320, 320},
    {"dome", "tilt = 20\neye_offset = [0, -0.3, 0.4]", 320, 320},
    {"opencv_pinhole", "fx = 260\nfy = 260\nk1 = -0.3\nk2 = 0.08\np1 = 0.002", 480, 270},
    {"opencv_fisheye", "fx = 140\nfy = 140\nk1 = 0.02\nk2 = -0.01", 480, 270},
    {"equirectangular", "", 512, 256},
    {"cylindrical", "", 512, 288},
    {"mercator", "", 480, 360},
    {"lambert_equal_area", "", 503, 160},
    {"stereographic", "fov = 220", 480, 270},
    {"panini", "fov = 150", 480, 270},
    {"cubemap", "", 384, 256},
    {"ods", "ipd = 0.6", 320, 320},
    {"light_field", "look_at = [0, 0, -5]\nfov = 50\ncolumns = 8\nrows = 6", 480, 360},
    {"integral", "columns = 16\nrows = 9\nwidth = 1.6\nlens_fov = 70", 640, 360},
    {"pushbroom", "length = 10", 480, 270},
    {"crossed_slits", "fov = 100\nslit_distance = 2.5", 480, 270},
};

int images(const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  for (const auto& p : camera_presets()) {
    const Shot* shot = nullptr;
    for (const auto& s : kShots)
      if (s.preset == p.name) shot = &s;
    if (!shot) {
      std::cerr << "no shot for preset " << p.name << "\n";
      return 1;
    }
    const VirtualCamera cam(make_preset(shot->preset, shot->toml, {shot->w, shot->h}));
    OutputImage img = render(cam, shot->w, shot->h);
    img.metadata["anamorph.camera"] = std::string(shot->preset) + ": " + shot->toml;
    write_png(dir / (std::string(p.name) + ".png"), img);
    std::cout << "wrote " << (dir / (std::string(p.name) + ".png")).string() << "\n";
  }
  return 0;
}

int tables(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) {
    std::cerr << file << ": cannot read\n";
    return 1;
  }
  std::stringstream buf;
  buf << in.rdbuf();
  std::string text = buf.str();
  for (const auto& p : camera_presets()) {
    const std::string open = "<!-- params:" + std::string(p.name) + " -->\n";
    const std::string close = "<!-- /params:" + std::string(p.name) + " -->";
    const size_t a = text.find(open), b = text.find(close);
    if (a == std::string::npos || b == std::string::npos || b < a) {
      std::cerr << file << ": no block " << open << "... " << close << " for preset " << p.name
                << "\n";
      return 1;
    }
    text.replace(a + open.size(), b - a - open.size(), preset_params_markdown(p));
  }
  std::ofstream(file) << text;
  std::cout << "updated " << file << "\n";
  return 0;
}

}  // namespace
}  // namespace anamorph

int main(int argc, char** argv) {
  const std::string mode = argc == 3 ? argv[1] : "";
  if (mode == "images") return anamorph::images(argv[2]);
  if (mode == "tables") return anamorph::tables(argv[2]);
  std::cerr << "usage: camera_preset_gallery images <dir> | tables <cameras.md>\n";
  return 2;
}
