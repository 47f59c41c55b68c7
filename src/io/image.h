// A decoded image in memory: what the readers return and textures and environments sample.
#pragma once

#include <cstddef>
#include <vector>

namespace anamorph {

// Linear float RGBA image in memory, top row first.
struct Image {
  int width = 0, height = 0, channels = 4;
  std::vector<float> pixels;  // width * height * channels
  float at(int x, int y, int c) const { return pixels[(size_t(y) * width + x) * channels + c]; }
  float& at(int x, int y, int c) { return pixels[(size_t(y) * width + x) * channels + c]; }
};

}  // namespace anamorph
