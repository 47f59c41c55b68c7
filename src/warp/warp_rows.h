// The pixels of a warp: for each pixel of the camera's image, its ray direction looked up in the
// source projection and the texture filtered there by the ray's footprint (camera/stmap.h:
// source_footprint). Shared by `anamorph warp` (app/warp_frame.h, which streams the rows to a
// file) and Python's anamorph.warp (an array).
#pragma once

#include <string>
#include <vector>

#include "camera/camera.h"
#include "camera/source_projection.h"
#include "warp/warp_texture.h"

namespace anamorph {

struct WarpView {
  const Camera& camera;
  const SourceProjection& source;
  const WarpTexture& texture;
  int width, height;
};

// Rows [y0, y0 + rows) of the camera's image into `rgba` (rows x width x 4 floats, straight
// colour, alpha the source's where the pixel has a ray the source shows, all 0 elsewhere).
// Thread-safe; each pixel's value depends on nothing but its position.
void warp_rows(const WarpView& v, int y0, int rows, float* rgba);

// The input's size fits the projection: width / height within half a pixel of its aspect, else
// ParamError (key "--source") naming `name` (the input) and both aspects.
void check_source_aspect(const SourceProjection& source, int width, int height,
                         const std::string& name);

// The whole image (height x width x 4 floats), rows in parallel.
std::vector<float> warp_image(const WarpView& v);

}  // namespace anamorph
