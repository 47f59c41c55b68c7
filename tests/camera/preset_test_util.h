// Shared by the preset tests: building presets from TOML text, printing rays, and the list of
// representative settings (every preset at least once) that the generic tests run over.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "camera/presets.h"
#include "camera/virtual_camera.h"

namespace anamorph::test {

inline std::string str(const Vec3& v) {
  std::ostringstream os;
  os.precision(17);
  os << "(" << v.x << ", " << v.y << ", " << v.z << ")";
  return os.str();
}
inline std::string str(const Vec2& v) {
  std::ostringstream os;
  os.precision(17);
  os << "(" << v.x << ", " << v.y << ")";
  return os.str();
}
inline std::string str(const std::vector<Vec2>& vs) {
  std::string s = "[";
  for (const auto& v : vs) s += (s.size() > 1 ? ", " : "") + str(v);
  return s + "]";
}

inline VirtualCamera camera(std::string_view preset, std::string_view toml, ImageInfo img) {
  return VirtualCamera(make_preset(preset, toml, img));
}

inline std::optional<CameraRay> ray(const Camera& cam, Vec2 uv) {
  CameraSample s;
  s.uv = uv;
  return cam.generate(s);
}

// Angle between two directions in degrees (robust near 0 and 180).
inline double angle_deg(const Vec3& a, const Vec3& b) {
  return degrees(std::atan2(length(cross(a, b)), dot(a, b)));
}

struct PresetCase {
  std::string preset;
  std::string toml;
  ImageInfo img;
  // Image position whose ray looks along look_at (NaN = not meaningful for this camera).
  Vec2 center{0.5, 0.5};
  std::string label() const {
    return preset + " {" + toml + "} " + std::to_string(img.width) + "x" +
           std::to_string(img.height);
  }
};

// gtest prints parameters with this (instead of their bytes).
inline void PrintTo(const PresetCase& c, std::ostream* os) { *os << c.label(); }

// A rig that is neither axis-aligned nor at the origin, so every test also exercises it.
inline constexpr const char* kRig =
    "look_from = [1, 2, 3]\nlook_at = [2, 2.5, -4]\nup = [0.1, 1, 0]\n";

inline std::vector<PresetCase> preset_cases() {
  const double nan = std::nan("");
  const std::string rig = kRig;
  return {
      {"perspective", rig + "fov = 60", {1920, 1080}},
      {"perspective", rig + "fov = 100\nfov_axis = \"diagonal\"", {1920, 1080}},
      {"perspective",
       rig + "fov = 40\nfov_axis = \"vertical\"\nlens_shift = [0.1, -0.2]",
       {1920, 1080},
       {nan, nan}},
      {"orthographic", rig + "view_width = 3", {1920, 1080}},
      {"fisheye", rig + "fov = 180", {1920, 1080}},
      {"fisheye", rig + "fov = 360", {1024, 1024}},
      {"fisheye", rig + "fov = 300\nmapping = \"equisolid\"", {1024, 1024}},
      {"fisheye",
       rig + "fov = 200\nmapping = \"stereographic\"\nfit = \"full_frame\"",
       {1920, 1080}},
      {"fisheye", rig + "fov = 170\nmapping = \"orthographic\"", {1080, 1920}},
      {"fisheye",
       rig + "fov = 131.78029288008932\nmapping = \"polynomial\"\npoly = [0, 1.2, 0, -0.1, 0.05]\n"
             "fit = \"pixels\"\ncircle_diameter = 1000",
       {1920, 1080}},
      {"mirror_ball", rig, {1024, 1024}, {nan, nan}},
      {"dome",
       rig + "tilt = 25\nradius = 2\neye_offset = [0.1, -0.3, 0.4]",
       {2048, 2048},
       {nan, nan}},
      {"opencv_pinhole",
       rig + "fx = 1400\nfy = 1390\ncx = 959.5\ncy = 539.5\nk1 = -0.28\nk2 = 0.09\nk3 = -0.01\n"
             "p1 = 0.001\np2 = -0.0005",
       {1920, 1080}},
      {"opencv_fisheye",
       rig + "fx = 600\nfy = 602\ncx = 959.5\ncy = 539.5\nk1 = 0.05\nk2 = -0.01\nk3 = 0.002\n"
             "k4 = -0.0003",
       {1920, 1080}},
      {"equirectangular", rig, {2048, 1024}},
      {"equirectangular",
       rig + "longitude_range = [-100, 80]\nlatitude_range = [-30, 60]",
       {1920, 1080},
       {100.0 / 180, 60.0 / 90}},
      {"cylindrical", rig, {1920, 1080}},
      {"cylindrical", rig + "projection = \"orthographic\"\nheight = 2", {1920, 1080}},
      {"mercator", rig, {2048, 2048}},
      {"lambert_equal_area", rig, {2048, 1024}},
      {"stereographic", rig + "fov = 270", {1920, 1080}},
      {"panini", rig + "fov = 150", {1920, 1080}},
      {"panini", rig + "fov = 160\ncompression = 2.5", {1920, 1080}},
      {"panini", rig + "fov = 70\nfov_axis = \"vertical\"\ncompression = 0.5", {1920, 1080}},
      {"cubemap", rig, {1536, 1024}, {nan, nan}},
      {"cubemap", rig + "layout = \"6x1\"\nconvention = \"opengl\"", {3072, 512}, {nan, nan}},
      {"ods", rig, {2048, 2048}, {0.5, 0.25}},
      {"ods",
       rig + "pole_merge = [60, 85]\nlayout = \"side_by_side\"\nipd = 0.3",
       {4096, 1024},
       {0.25, 0.5}},
      {"light_field", rig, {3360, 3360}, {nan, nan}},
      {"integral", rig + "columns = 24\nrows = 12\nwidth = 2", {1920, 1080}, {nan, nan}},
      {"pushbroom", rig, {1920, 1080}},
      {"crossed_slits", rig + "slit_distance = 2", {1920, 1080}},
      {"crossed_slits", rig + "slit_distance = -1\nfov = 90", {1920, 1080}},
  };
}

}  // namespace anamorph::test
