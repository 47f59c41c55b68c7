#include "app/calib_model.h"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <cmath>
#include <optional>

namespace anamorph::app {

namespace {

// The [camera] table of the scene as rendered (animation evaluated, overrides applied).
toml::table camera_table(const Scene& s) {
  toml::table root = toml::parse(s.effective_toml);
  if (const toml::table* cam = root["camera"].as_table()) return *cam;
  return {};
}

double number(const toml::table& cam, const char* key, double fallback) {
  return cam[key].value<double>().value_or(fallback);
}

// Pose from the rig (camera space to world): refused unless it is a rotation and a translation.
void set_pose(const Scene& s, Calibration* c) {
  const Mat4& m = s.camera->rig().matrix();
  Vec3 col[3];
  for (int j = 0; j < 3; ++j) col[j] = {m.m[0][j], m.m[1][j], m.m[2][j]};
  double worst = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) worst = std::max(worst, std::abs(dot(col[i], col[j]) - (i == j)));
  if (worst > 1e-9 || dot(cross(col[0], col[1]), col[2]) < 0)
    throw NoCalibration{"the camera's transform scales, shears or mirrors (no rigid pose)"};
  const Vec3 rows[3] = {col[0], -col[1], -col[2]};  // OpenCV's X, Y, Z in world
  const Vec3 centre{m.m[0][3], m.m[1][3], m.m[2][3]};
  for (int i = 0; i < 3; ++i) {
    c->R[size_t(i)] = {rows[i].x, rows[i].y, rows[i].z};
    c->t[i] = -dot(rows[i], centre);
  }
}

// OpenCV camera coordinates of world point p.
Vec3 to_camera(const Calibration& c, const Vec3& p) {
  Vec3 q;
  for (int i = 0; i < 3; ++i) {
    const auto& r = c.R[size_t(i)];
    q[i] = r[0] * p.x + r[1] * p.y + r[2] * p.z + c.t[i];
  }
  return q;
}

// OpenCV camera direction of the ray through image position uv, or nothing.
std::optional<Vec3> ray_at(const Scene& s, const Calibration& c, Vec2 uv) {
  const auto r = s.camera->generate({uv});
  if (!r) return std::nullopt;
  return to_camera(c, r->org + r->dir) - to_camera(c, r->org);
}

// perspective and the equidistant fisheye: the principal point is where the axis lands, the
// focal lengths from the rays a quarter of the image off it (x / z for the pinhole, theta for
// the fisheye, both exact in these models).
void measure_intrinsics(const Scene& s, Calibration* c) {
  const Vec3 ahead{-c->R[2][0], -c->R[2][1], -c->R[2][2]};
  const Vec3 centre{-(c->R[0][0] * c->t.x + c->R[1][0] * c->t.y + c->R[2][0] * c->t.z),
                    -(c->R[0][1] * c->t.x + c->R[1][1] * c->t.y + c->R[2][1] * c->t.z),
                    -(c->R[0][2] * c->t.x + c->R[1][2] * c->t.y + c->R[2][2] * c->t.z)};
  const std::vector<Vec2> axis = s.camera->project(centre - ahead);
  if (axis.size() != 1) throw NoCalibration{"the camera does not see along its axis"};
  const double W = c->width, H = c->height;
  c->cx = axis[0].x * W - 0.5, c->cy = axis[0].y * H - 0.5;
  const bool fisheye = c->model == Calibration::Model::KannalaBrandt;
  const auto angle = [&](const Vec3& d, double along) {
    if (!fisheye) return along / d.z;
    return std::atan2(std::hypot(d.x, d.y), d.z) * along / std::hypot(d.x, d.y);
  };
  const double off = 0.25 * std::min(W, H);
  const auto dx = ray_at(s, *c, {(c->cx + 0.5 + off) / W, (c->cy + 0.5) / H});
  const auto dy = ray_at(s, *c, {(c->cx + 0.5) / W, (c->cy + 0.5 + off) / H});
  if (!dx || !dy) throw NoCalibration{"the camera has no ray a quarter image off its axis"};
  c->fx = off / angle(*dx, dx->x);
  c->fy = off / angle(*dy, dy->y);
}

// opencv_pinhole and opencv_fisheye: the keys themselves, scaled from the calibration size to
// the rendered one.
void read_intrinsics(const toml::table& cam, Calibration* c) {
  double cw = c->width, ch = c->height;
  if (const toml::array* a = cam["calibration_size"].as_array(); a && a->size() == 2)
    cw = (*a)[0].value<double>().value_or(cw), ch = (*a)[1].value<double>().value_or(ch);
  const double sx = c->width / cw, sy = c->height / ch;
  c->fx = number(cam, "fx", 1) * sx, c->fy = number(cam, "fy", 1) * sy;
  c->cx = (number(cam, "cx", (cw - 1) / 2) + 0.5) * sx - 0.5;
  c->cy = (number(cam, "cy", (ch - 1) / 2) + 0.5) * sy - 0.5;
  const bool kb = c->model == Calibration::Model::KannalaBrandt;
  const std::vector<const char*> keys = kb ? std::vector<const char*>{"k1", "k2", "k3", "k4"}
                                           : std::vector<const char*>{"k1", "k2", "p1", "p2", "k3"};
  for (const char* k : keys) c->dist.push_back(number(cam, k, 0));
}

// The model against the camera's rays at a grid of pixels: the worst pixel error.
double check_against_rays(const Scene& s, const Calibration& c) {
  const int n = 9;
  double worst = 0;
  int seen = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const Vec2 uv{(i + 0.5) / n, (j + 0.5) / n};
      const auto r = s.camera->generate({uv});
      if (!r) continue;
      double px, py;
      if (!model_project(c, r->org + r->dir * 2.5, &px, &py)) continue;  // (beyond 90 degrees)
      ++seen;
      worst = std::max(
          {worst, std::abs(px - (uv.x * c.width - 0.5)), std::abs(py - (uv.y * c.height - 0.5))});
    }
  if (seen == 0) throw NoCalibration{"no pixel of the camera could be checked against the model"};
  return worst;
}

}  // namespace

Calibration calibration_of(const Scene& s, double* checked_px) {
  const toml::table cam = camera_table(s);
  const std::string preset = cam["preset"].value<std::string>().value_or("");
  Calibration c;
  c.preset = preset;
  c.width = s.render.width, c.height = s.render.height;
  if (preset == "perspective") {
    c.model = Calibration::Model::Pinhole;
  } else if (preset == "opencv_pinhole") {
    c.model = Calibration::Model::BrownConrady;
  } else if (preset == "opencv_fisheye") {
    c.model = Calibration::Model::KannalaBrandt;
  } else if (preset == "fisheye" &&
             cam["mapping"].value<std::string>().value_or("equidistant") == "equidistant") {
    c.model = Calibration::Model::KannalaBrandt;
    c.dist = {0, 0, 0, 0};
  } else {
    throw NoCalibration{
        preset.empty()
            ? std::string("the camera is not a preset (org/dir functions or a model's camera)")
            : fmt::format("preset \"{}\"{} has no model in these formats (they have the pinhole, "
                          "OpenCV's Brown-Conrady and OpenCV's fisheye / equidistant models)",
                          preset, preset == "fisheye" ? " with this mapping" : "")};
  }
  if (s.camera->moving()) throw NoCalibration{"the camera moves while the shutter is open"};
  if (cam.contains("coin")) throw NoCalibration{"the camera has coins (local deformations)"};
  set_pose(s, &c);
  if (preset == "opencv_pinhole" || preset == "opencv_fisheye")
    read_intrinsics(cam, &c);
  else
    measure_intrinsics(s, &c);
  const double worst = check_against_rays(s, c);
  if (!(worst <= 1e-6))
    throw NoCalibration{fmt::format(
        "the camera's rays differ from the {} model by up to {:.3g} px (keys beyond the model)",
        preset, worst)};
  if (checked_px) *checked_px = worst;
  return c;
}

bool model_project(const Calibration& c, const Vec3& p, double* px, double* py) {
  const Vec3 q = to_camera(c, p);
  if (!(q.z > 0)) return false;
  const double x = q.x / q.z, y = q.y / q.z;
  double xd = x, yd = y;
  const std::vector<double>& k = c.dist;
  if (c.model == Calibration::Model::BrownConrady) {
    const double r2 = x * x + y * y, L = 1 + r2 * (k[0] + r2 * (k[1] + r2 * k[4]));
    xd = x * L + 2 * k[2] * x * y + k[3] * (r2 + 2 * x * x);
    yd = y * L + k[2] * (r2 + 2 * y * y) + 2 * k[3] * x * y;
  } else if (c.model == Calibration::Model::KannalaBrandt) {
    const double r = std::hypot(x, y);
    const double th = std::atan(r), t2 = th * th;
    const double td = th * (1 + t2 * (k[0] + t2 * (k[1] + t2 * (k[2] + t2 * k[3]))));
    const double s = r > 0 ? td / r : 1;
    xd = x * s, yd = y * s;
  }
  *px = c.fx * xd + c.cx, *py = c.fy * yd + c.cy;
  return true;
}

Vec3 rotation_vector(const Mat3& R) {
  const double tr = R[0][0] + R[1][1] + R[2][2];
  const Vec3 s{R[2][1] - R[1][2], R[0][2] - R[2][0], R[1][0] - R[0][1]};  // 2 sin(a) axis
  const double sn = 0.5 * length(s), cs = 0.5 * (tr - 1);
  const double a = std::atan2(sn, cs);
  if (sn > 1e-6) return s * (a / (2 * sn));
  if (cs > 0) return s * 0.5;  // (small angles: sin a ~ a)
  // Near pi: the axis from the symmetric part, R + I = 2 n n^T.
  Vec3 n{std::sqrt(std::max(0.0, (R[0][0] + 1) / 2)), std::sqrt(std::max(0.0, (R[1][1] + 1) / 2)),
         std::sqrt(std::max(0.0, (R[2][2] + 1) / 2))};
  if (R[0][1] + R[1][0] < 0) n.y = -n.y;
  if (R[0][2] + R[2][0] < 0) n.z = -n.z;
  return normalize(n) * a;
}

Mat3 rotation_matrix(const Vec3& rvec) {
  const double a = length(rvec);
  Mat3 R{};
  if (!(a > 0)) {
    for (size_t i = 0; i < 3; ++i) R[i][i] = 1;
    return R;
  }
  const Vec3 n = rvec / a;
  const double c = std::cos(a), s = std::sin(a), C = 1 - c;
  R = {{{c + n.x * n.x * C, n.x * n.y * C - n.z * s, n.x * n.z * C + n.y * s},
        {n.y * n.x * C + n.z * s, c + n.y * n.y * C, n.y * n.z * C - n.x * s},
        {n.z * n.x * C - n.y * s, n.z * n.y * C + n.x * s, c + n.z * n.z * C}}};
  return R;
}

std::array<double, 4> quaternion(const Mat3& R) {
  const Vec3 rv = rotation_vector(R);
  const double a = length(rv);
  if (!(a > 0)) return {1, 0, 0, 0};
  const Vec3 v = rv * (std::sin(a / 2) / a);
  return {std::cos(a / 2), v.x, v.y, v.z};
}

}  // namespace anamorph::app
