// `anamorph calib --import`: OpenCV FileStorage files (JSON or YAML) and Kalibr camchains read
// back as a Calibration. YAML is read with yaml-cpp and turned into JSON, so both OpenCV flavours
// share one reader.
#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "app/calib_formats.h"

namespace anamorph::app {

namespace {

using Model = Calibration::Model;
using nlohmann::json;

[[noreturn]] void fail(const std::string& file, const std::string& key, const std::string& why) {
  throw std::runtime_error(fmt::format("{}: key {}: {}", file, key, why));
}

// A YAML scalar as JSON: an integer, a number (OpenCV writes "0." and ".Inf"), or a string.
json scalar(const std::string& v) {
  if (v.empty()) return v;
  size_t used = 0;
  try {
    const long long i = std::stoll(v, &used);
    if (used == v.size()) return i;
    const double d = std::stod(v, &used);
    if (used == v.size()) return d;
  } catch (const std::exception&) {
  }
  return v;
}

json to_json(const YAML::Node& n) {
  if (n.IsMap()) {
    json j = json::object();
    for (const auto& kv : n) j[kv.first.as<std::string>()] = to_json(kv.second);
    return j;
  }
  if (n.IsSequence()) {
    json j = json::array();
    for (const auto& e : n) j.push_back(to_json(e));
    return j;
  }
  if (n.IsScalar()) return n.Tag() == "!" ? json(n.Scalar()) : scalar(n.Scalar());  // "quoted"
  return nullptr;
}

// YAML as JSON. OpenCV's FileStorage starts with "%YAML:1.0", not a directive YAML parsers know.
json read_yaml(const std::string& name, std::istream& in) {
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (text.rfind("%YAML:", 0) == 0) text.erase(0, text.find('\n'));  // (lines keep their numbers)
  try {
    return to_json(YAML::Load(text));
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(
        fmt::format("{}:{}:{}: not YAML: {}", name, e.mark.line + 1, e.mark.column + 1, e.msg));
  }
}

// Numbers of j[key] (an array, or an opencv-matrix's data), all finite; `count` 0: any number.
std::vector<double> numbers(const std::string& file, const json& j, const std::string& key,
                            size_t count, bool required) {
  std::vector<double> v;
  if (!j.is_object() || !j.contains(key) || j[key].is_null()) {
    if (required) fail(file, key, "missing");
    return v;
  }
  const json* data = &j[key];
  if (data->is_object()) {
    if (!data->contains("data") || !(*data)["data"].is_array())
      fail(file, key, "expected an opencv-matrix with data");
    data = &(*data)["data"];
  }
  if (!data->is_array()) fail(file, key, "expected a list of numbers");
  for (const auto& x : *data) {
    if (x.is_array()) {  // rows of a matrix (Kalibr's T_cam_imu)
      for (const auto& y : x) {
        if (!y.is_number() || !std::isfinite(y.get<double>())) fail(file, key, "expected numbers");
        v.push_back(y.get<double>());
      }
      continue;
    }
    if (!x.is_number() || !std::isfinite(x.get<double>()))
      fail(file, key, "expected finite numbers");
    v.push_back(x.get<double>());
  }
  if (count && v.size() != count) fail(file, key, fmt::format("expected {} numbers", count));
  return v;
}

int positive(const std::string& file, const json& j, const std::string& key) {
  if (!j.is_object() || !j.contains(key) || !j[key].is_number_integer() || j[key].get<int>() < 1)
    fail(file, key, "expected a positive integer");
  return j[key].get<int>();
}

// Distortion coefficients beyond the model's `want` must be 0 (OpenCV writes 5, 8, 12 or 14).
void set_distortion(const std::string& file, const std::string& key, std::vector<double> d,
                    size_t want, Calibration* c) {
  for (size_t i = want; i < d.size(); ++i)
    if (d[i] != 0)
      fail(file, key, fmt::format("coefficient {} is not 0 (only {} are supported)", i + 1, want));
  d.resize(want, 0.0);
  c->dist = d;
}

Calibration read_opencv(const std::string& file, const json& j) {
  Calibration c;
  c.width = positive(file, j, "image_width"), c.height = positive(file, j, "image_height");
  const std::vector<double> K = numbers(file, j, "camera_matrix", 9, true);
  if (K[1] != 0 || K[3] != 0 || K[6] != 0 || K[7] != 0 || K[8] != 1 || !(K[0] > 0) || !(K[4] > 0))
    fail(file, "camera_matrix", "expected [fx 0 cx; 0 fy cy; 0 0 1] with fx, fy > 0 (no skew)");
  c.fx = K[0], c.cx = K[2], c.fy = K[4], c.cy = K[5];
  // distortion_model (ours) or fisheye_model: 1 (OpenCV's calibration tutorial).
  const bool fisheye = (j.contains("distortion_model") && j["distortion_model"] == "fisheye") ||
                       (j.contains("fisheye_model") && j["fisheye_model"] == 1);
  c.model = fisheye ? Model::KannalaBrandt : Model::BrownConrady;
  std::vector<double> d = numbers(file, j, "distortion_coefficients", 0, false);
  if (d.size() == 4 && !fisheye) d.push_back(0);  // (k1 k2 p1 p2)
  set_distortion(file, "distortion_coefficients", d, fisheye ? 4 : 5, &c);
  const std::vector<double> r = numbers(file, j, "rvec", 3, false),
                            t = numbers(file, j, "tvec", 3, false);
  c.R = rotation_matrix(r.empty() ? Vec3{} : Vec3{r[0], r[1], r[2]});
  if (!t.empty()) c.t = {t[0], t[1], t[2]};
  return c;
}

Calibration read_kalibr(const std::string& file, const json& cam) {
  const auto text = [&](const char* key) {
    if (!cam.contains(key) || !cam[key].is_string()) fail(file, key, "missing (a name)");
    return cam[key].get<std::string>();
  };
  if (const std::string m = text("camera_model"); m != "pinhole")
    fail(file, "cam0.camera_model",
         fmt::format("\"{}\": only pinhole is read (with radtan or equidistant)", m));
  Calibration c;
  const std::vector<double> in = numbers(file, cam, "intrinsics", 4, true);
  c.fx = in[0], c.fy = in[1], c.cx = in[2], c.cy = in[3];
  if (!(c.fx > 0) || !(c.fy > 0)) fail(file, "cam0.intrinsics", "expected fu, fv > 0");
  const std::vector<double> res = numbers(file, cam, "resolution", 2, true);
  if (!(res[0] >= 1 && res[1] >= 1 && res[0] == std::floor(res[0]) && res[1] == std::floor(res[1])))
    fail(file, "cam0.resolution", "expected two positive integers");
  c.width = int(res[0]), c.height = int(res[1]);
  const std::string model = cam.contains("distortion_model") ? text("distortion_model") : "none";
  std::vector<double> d = numbers(file, cam, "distortion_coeffs", 0, false);
  if (model == "equidistant") {
    c.model = Model::KannalaBrandt;
    set_distortion(file, "cam0.distortion_coeffs", d, 4, &c);
  } else if (model == "radtan" || model == "none") {
    c.model = Model::BrownConrady;
    if (model == "none") d.clear();
    set_distortion(file, "cam0.distortion_coeffs", d, 4, &c);
    c.dist.push_back(0);  // k3
  } else {
    fail(file, "cam0.distortion_model",
         fmt::format("\"{}\": only radtan, equidistant or none are read", model));
  }
  const std::vector<double> T = numbers(file, cam, "T_cam_imu", 16, false);
  c.R = rotation_matrix({});
  if (!T.empty()) {
    for (size_t i = 0; i < 3; ++i) c.R[i] = {T[4 * i], T[4 * i + 1], T[4 * i + 2]};
    c.t = {T[3], T[7], T[11]};
    double worst = 0;
    for (size_t i = 0; i < 3; ++i)
      for (size_t k = 0; k < 3; ++k)
        worst = std::max(worst, std::abs(c.R[i][0] * c.R[k][0] + c.R[i][1] * c.R[k][1] +
                                         c.R[i][2] * c.R[k][2] - (i == k)));
    if (worst > 1e-6 || T[12] != 0 || T[13] != 0 || T[14] != 0 || T[15] != 1)
      fail(file, "cam0.T_cam_imu", "expected a rigid transform [R t; 0 0 0 1]");
  }
  return c;
}

}  // namespace

Calibration read_calibration(const std::filesystem::path& path) {
  const std::string file = path.string();
  std::ifstream in(path);
  if (!in) throw std::runtime_error(file + ": cannot be read");
  const std::string ext = path.extension().string();
  json j;
  if (ext == ".json") {
    try {
      j = json::parse(in);
    } catch (const json::exception& e) {
      throw std::runtime_error(fmt::format("{}: not JSON ({})", file, e.what()));
    }
  } else if (ext == ".yml" || ext == ".yaml") {
    j = read_yaml(file, in);
  } else {
    throw std::runtime_error(file +
                             ": --import reads OpenCV FileStorage (.json, .yml, .yaml) and "
                             "Kalibr camchains (.yaml)");
  }
  if (j.is_object() && j.contains("cam0") && j["cam0"].is_object())
    return read_kalibr(file, j["cam0"]);
  return read_opencv(file, j);
}

}  // namespace anamorph::app
