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

Calibration read_opencv_json(const std::filesystem::path& file) {
  const std::string name = file.string();
  std::ifstream in(file);
  if (!in) throw std::runtime_error(name + ": cannot be read");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(fmt::format(
        "{}: not JSON ({}); --import reads OpenCV FileStorage JSON (cv2.FileStorage('x.json'))",
        name, e.what()));
  }
  const auto matrix = [&](const char* key, size_t rows, size_t cols, bool required) {
    std::vector<double> v;
    const auto fail = [&](const std::string& why) {
      throw std::runtime_error(fmt::format("{}: key {}: {}", name, key, why));
    };
    if (!j.is_object() || !j.contains(key)) {
      if (required) fail("missing");
      return v;
    }
    const nlohmann::json& m = j[key];
    if (!m.is_object() || !m.contains("data") || !m["data"].is_array())
      fail("expected an opencv-matrix with data");
    for (const auto& x : m["data"]) {
      if (!x.is_number() || !std::isfinite(x.get<double>())) fail("expected finite numbers");
      v.push_back(x.get<double>());
    }
    if (rows && v.size() != rows * cols) fail(fmt::format("expected {} numbers", rows * cols));
    return v;
  };
  Calibration c;
  for (const char* key : {"image_width", "image_height"})
    if (!j.is_object() || !j.contains(key) || !j[key].is_number_integer() || j[key].get<int>() < 1)
      throw std::runtime_error(fmt::format("{}: key {}: expected a positive integer", name, key));
  c.width = j["image_width"].get<int>(), c.height = j["image_height"].get<int>();
  const std::vector<double> K = matrix("camera_matrix", 3, 3, true);
  if (K[1] != 0 || K[3] != 0 || K[6] != 0 || K[7] != 0 || K[8] != 1 || !(K[0] > 0) || !(K[4] > 0))
    throw std::runtime_error(name + ": key camera_matrix: expected [fx 0 cx; 0 fy cy; 0 0 1] " +
                             "with fx, fy > 0 (no skew)");
  c.fx = K[0], c.cx = K[2], c.fy = K[4], c.cy = K[5];
  const bool fisheye = j.value("distortion_model", std::string()) == "fisheye";
  c.model = fisheye ? Model::KannalaBrandt : Model::BrownConrady;
  c.dist = matrix("distortion_coefficients", 0, 0, false);
  const size_t want = fisheye ? 4 : 5;
  if (c.dist.size() == 4 && !fisheye) c.dist.push_back(0);  // (k1 k2 p1 p2)
  for (size_t i = want; i < c.dist.size(); ++i)
    if (c.dist[i] != 0)
      throw std::runtime_error(fmt::format(
          "{}: key distortion_coefficients: coefficient {} is not 0 (only {} are supported)", name,
          i + 1, want));
  c.dist.resize(want, 0.0);
  const std::vector<double> r = matrix("rvec", 3, 1, false), t = matrix("tvec", 3, 1, false);
  c.R = rotation_matrix(r.empty() ? Vec3{} : Vec3{r[0], r[1], r[2]});
  if (!t.empty()) c.t = {t[0], t[1], t[2]};
  return c;
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
