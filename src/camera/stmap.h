// STMaps of a camera: for each of its pixels, where a source projection
// (camera/source_projection.h) shows the direction that pixel sees, and the inverse (for each
// source pixel, the camera pixel that sees its direction). What `anamorph stmap` writes and
// `anamorph warp` samples through.
//
// Convention (Nuke's STMap, Natron's STMapOFX, Blender's Map UV): s = u of the source, left to
// right in [0,1] with pixel centers at (x + 0.5) / W; t from the BOTTOM of the source:
// t = 1 - v = 1 - (y + 0.5) / H at the center of row y (row 0 on top).
// Only a central camera (one eye point: every ray leaves the same origin) is a reprojection of
// directions; others are refused (NonCentralCamera), or mapped through a DepthSphere.
#pragma once

#include <optional>
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

// The mean origin of the camera's rays on the same grid (a non-central camera's eye for a
// DepthSphere: the centre of an omnidirectional stereo circle, of a light-field array).
Vec3 mean_origin(const Camera& camera, int width, int height);

// A non-central camera as a reprojection: the world taken as a sphere of radius `depth` about
// `eye` (what a 360-degree image is to its viewer). A camera ray is carried to where it leaves
// that sphere and seen from the eye: exact for points at that distance from the eye, and, for a
// central camera at the eye, its own directions.
struct DepthSphere {
  Vec3 eye;
  double depth = 1;
};
// The ray seen from the sphere's eye: origin the eye, unit direction toward the ray's point on
// the sphere, and the differentials of that direction (dorg zero); none when the ray does not
// leave the sphere ahead (its origin outside it, pointing away).
std::optional<CameraRay> seen_from_eye(const CameraRay& r, const DepthSphere& s);

// The sphere a map goes through: with `depth` (> 0), {mean_origin, depth} for any camera;
// without, a central camera's {central_origin, 1} (NonCentralCamera for another).
DepthSphere map_sphere(const Camera& camera, int width, int height,
                       std::optional<double> depth = std::nullopt);

// A map of width x height pixels, top row first: st (2 floats per pixel, the convention above),
// alpha (1 where the pixel has a ray and the other side shows its direction, else 0, st 0),
// direction (3 floats, the unit world direction; 0 where none).
struct StMap {
  int width = 0, height = 0;
  std::vector<float> st, alpha, direction;
};

// Camera pixel -> source position (through `sphere` when given).
StMap forward_stmap(const Camera& camera, const SourceProjection& source, int width, int height,
                    const std::optional<DepthSphere>& sphere = std::nullopt);

// Source pixel (source_width x source_height) -> camera position (s = u, t = 1 - v of the
// camera's image): the first image position Camera::project gives for the point of the sphere in
// the pixel's direction from its eye whose ray goes toward that point. A central camera's sphere
// is {central_origin, 1}.
StMap inverse_stmap(const Camera& camera, const DepthSphere& sphere, const SourceProjection& source,
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
