// STMaps of a camera: for each of its pixels, where a source projection
// (camera/source_projection.h) shows the direction that pixel sees, and the inverse (for each
// source pixel, the camera pixel that sees its direction). What `anamorph stmap` writes and
// `anamorph warp` samples through.
//
// Convention (Nuke's STMap, Natron's STMapOFX, Blender's Map UV): s = u of the source, left to
// right in [0,1] with pixel centers at (x + 0.5) / W; t from the BOTTOM of the source:
// t = 1 - v = 1 - (y + 0.5) / H at the center of row y (row 0 on top).
// Only a central camera (one eye point: every ray leaves the same origin) is a reprojection of
// directions; others are refused (NonCentralCamera).
#pragma once

#include <stdexcept>
#include <vector>

#include "camera/camera.h"
#include "camera/source_projection.h"

namespace anamorph {

struct NonCentralCamera : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The camera's one origin, from its rays on a grid over the image (lens at its center, time 0);
// throws NonCentralCamera naming two pixels whose origins differ, or when no ray exists.
Vec3 central_origin(const Camera& camera, int width, int height);

// A map of width x height pixels, top row first: st (2 floats per pixel, the convention above),
// alpha (1 where the pixel has a ray and the other side shows its direction, else 0, st 0),
// direction (3 floats, the unit world direction; 0 where none).
struct StMap {
  int width = 0, height = 0;
  std::vector<float> st, alpha, direction;
};

// Camera pixel -> source position.
StMap forward_stmap(const Camera& camera, const SourceProjection& source, int width, int height);

// Source pixel (source_width x source_height) -> camera position (s = u, t = 1 - v of the
// camera's image): the first image position Camera::project gives for the direction whose ray
// has that direction. `origin` is central_origin's.
StMap inverse_stmap(const Camera& camera, const Vec3& origin, const SourceProjection& source,
                    int source_width, int source_height);

// The source position of a unit direction and its change per target pixel along x and y, from
// the ray's differentials (ddir_du / width, ddir_dv / height) by a one-sided difference of half
// a pixel through `source` (ahead, else behind), doubled; across u's seam (wraps_u) the
// difference is taken the short way. Derivatives are 0 where a neighbour has no source position
// on either side.
struct SourceFootprint {
  Vec2 uv, duv_dx, duv_dy;
};
std::optional<SourceFootprint> source_footprint(const SourceProjection& source,
                                                const CameraRay& ray, int width, int height);

}  // namespace anamorph
