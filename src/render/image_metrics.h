// Image error metrics for comparisons against references: RMSE, mean absolute difference, mean
// relative difference, and SSIM (Wang et al. 2004, 8x8 windows, on luminance).
#pragma once

#include <vector>

namespace anamorph {

struct ImageMetrics {
  double rmse = 0;           // over RGB, linear values
  double rmse_display = 0;   // over RGB as displayed: clamped to [0,1], sRGB-encoded
  double mean_abs = 0;       // over RGB
  double mean_relative = 0;  // |a - b| / (|b| + 0.01), over RGB
  double ssim = 1;           // on display-clamped luminance
};

// a and b: interleaved RGBA (alpha ignored), width * height * 4.
ImageMetrics compare_images(const std::vector<float>& a, const std::vector<float>& b, int width,
                            int height);

}  // namespace anamorph
