// The scene camera as a calibration in OpenCV's models, for `anamorph calib` (docs/vision.md):
// which presets have one, their intrinsics and pose in OpenCV's conventions, the models'
// forward maps, and the rotation helpers the file formats need.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "math/vec.h"
#include "scene/scene.h"

namespace anamorph::app {

using Mat3 = std::array<std::array<double, 3>, 3>;

// OpenCV's conventions throughout: camera axes X right, Y down, Z forward (anamorph's camera
// space is x right, y up, -z forward, so (X, Y, Z) = (x, -y, -z)); pixel (px, py) with the
// centre of the top-left pixel at (0, 0), so px = u W - 0.5, py = v H - 0.5 for anamorph's
// image position (u, v) in [0, 1]^2 (u left to right, v top to bottom). Pose: a world point P
// is R P + t in camera coordinates.
struct Calibration {
  enum class Model { Pinhole, BrownConrady, KannalaBrandt };
  Model model = Model::Pinhole;
  std::string preset;  // the scene camera it describes
  int width = 0, height = 0;
  double fx = 1, fy = 1, cx = 0, cy = 0;
  // Pinhole: none. BrownConrady: k1 k2 p1 p2 k3 (cv::projectPoints' order). KannalaBrandt:
  // k1 k2 k3 k4 (cv::fisheye).
  std::vector<double> dist;
  Mat3 R{};
  Vec3 t;
};

// Thrown when the scene camera has no such model; the message says why.
struct NoCalibration {
  std::string why;
};

// The calibration of the scene's camera at the frame loaded; checked against the camera's own
// rays at a grid of pixels (worst pixel error in *checked_px). Throws NoCalibration.
Calibration calibration_of(const Scene& s, double* checked_px);

// The pixel of world point p under the model (OpenCV's formulas); false behind the camera.
bool model_project(const Calibration& c, const Vec3& p, double* px, double* py);

// Rodrigues' rotation vector and back (as cv::Rodrigues).
Vec3 rotation_vector(const Mat3& R);
Mat3 rotation_matrix(const Vec3& rvec);
// Unit quaternion (w, x, y, z) with w >= 0, Hamilton's convention (COLMAP's images.txt).
std::array<double, 4> quaternion(const Mat3& R);

}  // namespace anamorph::app
