// The file layouts of `anamorph calib`: OpenCV's FileStorage (YAML or JSON), COLMAP's text model
// (cameras.txt, images.txt, points3D.txt), anamorph's own JSON, and the scene camera (TOML) of
// an imported OpenCV file. Conventions in app/calib_model.h and docs/vision.md.
#pragma once

#include <filesystem>
#include <string>

#include "app/calib_model.h"

namespace anamorph::app {

// OpenCV FileStorage text: YAML ("%YAML:1.0") or, with `json`, FileStorage's JSON flavour.
// Keys image_width, image_height, camera_matrix, distortion_model ("plumb_bob" or "fisheye"),
// distortion_coefficients, rvec, tvec (world to camera, as cv::projectPoints takes them).
std::string opencv_text(const Calibration& c, bool json);

// Kalibr's camchain YAML: cam0 with camera_model pinhole, distortion_model radtan (k1 k2 p1 p2)
// or equidistant (Kannala-Brandt), intrinsics, distortion_coeffs, resolution, and T_cam_imu the
// world-to-camera pose. Throws NoCalibration for a Brown-Conrady camera with k3 != 0.
std::string kalibr_text(const Calibration& c);

// COLMAP's cameras.txt and images.txt lines (one camera, one image named `image_name`).
std::string colmap_cameras(const Calibration& c);
std::string colmap_images(const Calibration& c, const std::string& image_name);

// anamorph's JSON: the model, intrinsics, distortion, pose and the conventions spelled out.
std::string calibration_json(const Calibration& c);

// A calibration file read back (app/calib_import.cpp): OpenCV FileStorage JSON or YAML (as
// opencv_text writes, cv2.FileStorage saves or OpenCV's calibration samples write) or a Kalibr
// camchain (YAML with cam0). Throws std::runtime_error naming the file and key for bad input.
Calibration read_calibration(const std::filesystem::path& file);

// The scene keys ([image] and [camera]) of a calibration: opencv_pinhole or opencv_fisheye.
std::string camera_toml(const Calibration& c, const std::string& from);

}  // namespace anamorph::app
