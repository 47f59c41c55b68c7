#include "app/calib_formats.h"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace anamorph::app {

namespace {

using Model = Calibration::Model;

std::string g17(double x) { return fmt::format("{:.17g}", x); }

std::string list(const std::vector<double>& v, const char* sep = ", ") {
  std::string s;
  for (size_t i = 0; i < v.size(); ++i) s += (i ? sep : "") + g17(v[i]);
  return s;
}

std::vector<double> camera_matrix(const Calibration& c) {
  return {c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1};
}

// Zeros for the pinhole: cv::projectPoints takes the five Brown-Conrady coefficients.
std::vector<double> coefficients(const Calibration& c) {
  return c.model == Model::Pinhole ? std::vector<double>(5, 0.0) : c.dist;
}

std::vector<double> rvec(const Calibration& c) {
  const Vec3 r = rotation_vector(c.R);
  return {r.x, r.y, r.z};
}

const char* distortion_model(const Calibration& c) {
  return c.model == Model::KannalaBrandt ? "fisheye" : "plumb_bob";
}

struct Matrix {
  const char* name;
  int rows, cols;
  std::vector<double> data;
};

std::vector<Matrix> matrices(const Calibration& c) {
  return {{"camera_matrix", 3, 3, camera_matrix(c)},
          {"distortion_coefficients", 1, int(coefficients(c).size()), coefficients(c)},
          {"rvec", 3, 1, rvec(c)},
          {"tvec", 3, 1, {c.t.x, c.t.y, c.t.z}}};
}

}  // namespace

std::string opencv_text(const Calibration& c, bool json) {
  std::string s;
  if (json) {
    s = fmt::format("{{\n  \"image_width\": {},\n  \"image_height\": {},\n", c.width, c.height);
    s += fmt::format("  \"distortion_model\": \"{}\",\n", distortion_model(c));
    const std::vector<Matrix> m = matrices(c);
    for (size_t i = 0; i < m.size(); ++i)
      s += fmt::format(
          "  \"{}\": {{\"type_id\": \"opencv-matrix\", \"rows\": {}, \"cols\": {}, \"dt\": "
          "\"d\", \"data\": [{}]}}{}\n",
          m[i].name, m[i].rows, m[i].cols, list(m[i].data), i + 1 < m.size() ? "," : "");
    return s + "}\n";
  }
  s = fmt::format(
      "%YAML:1.0\n---\n# anamorph calib: preset {}; OpenCV pixels (top-left pixel centre at 0,0),"
      "\n# camera X right, Y down, Z forward; x_cam = R(rvec) x_world + tvec\n"
      "image_width: {}\nimage_height: {}\ndistortion_model: \"{}\"\n",
      c.preset, c.width, c.height, distortion_model(c));
  for (const Matrix& m : matrices(c))
    s += fmt::format("{}: !!opencv-matrix\n   rows: {}\n   cols: {}\n   dt: d\n   data: [ {} ]\n",
                     m.name, m.rows, m.cols, list(m.data));
  return s;
}

std::string kalibr_text(const Calibration& c) {
  const bool kb = c.model == Model::KannalaBrandt;
  std::vector<double> d = kb ? c.dist : std::vector<double>(4, 0.0);
  if (c.model == Model::BrownConrady) {
    if (c.dist[4] != 0)
      throw NoCalibration{
          "Kalibr's radtan model has k1 k2 p1 p2 only, and this camera's k3 is not 0"};
    d.assign(c.dist.begin(), c.dist.begin() + 4);
  }
  std::string s = fmt::format(
      "# anamorph calib: preset {}; Kalibr camchain, OpenCV's pixels (top-left pixel centre at\n"
      "# 0,0) and camera axes (X right, Y down, Z forward); T_cam_imu: the scene's world frame to\n"
      "# the camera (anamorph has no IMU: its world stands for it), x_cam = T_cam_imu x_world\n"
      "cam0:\n  camera_model: pinhole\n  intrinsics: [{}]\n  distortion_model: {}\n"
      "  distortion_coeffs: [{}]\n  resolution: [{}, {}]\n  T_cam_imu:\n",
      c.preset, list({c.fx, c.fy, c.cx, c.cy}), kb ? "equidistant" : "radtan", list(d), c.width,
      c.height);
  for (size_t i = 0; i < 3; ++i)
    s += fmt::format("  - [{}]\n", list({c.R[i][0], c.R[i][1], c.R[i][2], c.t[int(i)]}));
  return s + "  - [0, 0, 0, 1]\n";
}

std::string colmap_cameras(const Calibration& c) {
  // COLMAP puts the top-left pixel's centre at (0.5, 0.5): its cx, cy are OpenCV's + 0.5.
  std::vector<double> p{c.fx, c.fy, c.cx + 0.5, c.cy + 0.5};
  const char* model = "PINHOLE";
  if (c.model == Model::KannalaBrandt) {
    model = "OPENCV_FISHEYE";
    p.insert(p.end(), c.dist.begin(), c.dist.end());
  } else if (c.model == Model::BrownConrady) {
    model = c.dist[4] == 0 ? "OPENCV" : "FULL_OPENCV";
    p.insert(p.end(), c.dist.begin(), c.dist.begin() + 4);
    if (c.dist[4] != 0) p.insert(p.end(), {c.dist[4], 0, 0, 0});
  }
  return fmt::format(
      "# Camera list with one line of data per camera:\n"
      "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n# Number of cameras: 1\n1 {} {} {} {}\n",
      model, c.width, c.height, list(p, " "));
}

std::string colmap_images(const Calibration& c, const std::string& image_name) {
  const std::array<double, 4> q = quaternion(c.R);
  return fmt::format(
      "# Image list with two lines of data per image:\n"
      "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
      "#   POINTS2D[] as (X, Y, POINT3D_ID)\n"
      "# Number of images: 1, mean observations per image: 0\n1 {} {} 1 {}\n\n",
      list({q[0], q[1], q[2], q[3]}, " "), list({c.t.x, c.t.y, c.t.z}, " "), image_name);
}

std::string calibration_json(const Calibration& c) {
  nlohmann::ordered_json j;
  j["preset"] = c.preset;
  j["model"] = c.model == Model::Pinhole        ? "pinhole"
               : c.model == Model::BrownConrady ? "opencv_brown_conrady"
                                                : "opencv_fisheye_kannala_brandt";
  j["image_size"] = {c.width, c.height};
  j["fx"] = c.fx, j["fy"] = c.fy, j["cx"] = c.cx, j["cy"] = c.cy;
  j["distortion"] = coefficients(c);
  j["distortion_order"] = c.model == Model::KannalaBrandt ? "k1 k2 k3 k4" : "k1 k2 p1 p2 k3";
  j["R_camera_from_world"] = c.R;
  j["t_camera_from_world"] = {c.t.x, c.t.y, c.t.z};
  j["rvec"] = rvec(c);
  j["conventions"] = {
      {"camera_axes", "OpenCV: X right, Y down, Z forward; anamorph (x, y, z) = (X, -Y, -Z)"},
      {"pixels", "OpenCV: top-left pixel centre at (0, 0); px = u W - 0.5, py = v H - 0.5"},
      {"pose", "x_camera = R x_world + t"}};
  return j.dump(2) + "\n";
}

std::string camera_toml(const Calibration& c, const std::string& from) {
  // The camera centre and OpenCV's Z (forward) and -Y (up) in world.
  Vec3 centre, fwd, up;
  for (int i = 0; i < 3; ++i) {
    centre -= Vec3{c.R[size_t(i)][0], c.R[size_t(i)][1], c.R[size_t(i)][2]} * c.t[i];
    fwd[i] = c.R[2][size_t(i)], up[i] = -c.R[1][size_t(i)];
  }
  const Vec3 at = centre + fwd;
  const bool kb = c.model == Model::KannalaBrandt;
  std::string s = fmt::format(
      "# from {} (anamorph calib --import)\n[image]\nwidth = {}\nheight = {}\n\n[camera]\n"
      "preset = \"{}\"\nfx = {}\nfy = {}\ncx = {}\ncy = {}\n",
      from, c.width, c.height, kb ? "opencv_fisheye" : "opencv_pinhole", g17(c.fx), g17(c.fy),
      g17(c.cx), g17(c.cy));
  const std::vector<const char*> keys = kb ? std::vector<const char*>{"k1", "k2", "k3", "k4"}
                                           : std::vector<const char*>{"k1", "k2", "p1", "p2", "k3"};
  for (size_t i = 0; i < keys.size(); ++i) s += fmt::format("{} = {}\n", keys[i], g17(c.dist[i]));
  s += fmt::format("look_from = [{}]\nlook_at = [{}]\nup = [{}]\n",
                   list({centre.x, centre.y, centre.z}), list({at.x, at.y, at.z}),
                   list({up.x, up.y, up.z}));
  return s;
}

}  // namespace anamorph::app
