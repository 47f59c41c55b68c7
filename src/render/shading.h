// From a hit to what its material reads: the pixel's footprint at the hit, texture coordinates
// filtered by it, and the shading point (material/material.h).
#pragma once

#include "accel/accel.h"
#include "camera/camera.h"
#include "material/material.h"

namespace anamorph {

// World-space footprint of one pixel at a hit, from the camera ray's differentials scaled to a
// pixel (du = 1/width, dv = 1/height, shrunk for several samples per pixel).
struct Footprint {
  Vec3 dpdx, dpdy;
  double spread = 0;  // growth of the footprint's width per unit distance (a ray cone)
};
Footprint footprint_at(const CameraRay& r, double du, double dv, const Hit& h);
// The footprint carried along a mirror or refracted ray to its next hit, as a ray cone: the
// width at the last hit plus distance times spread, isotropic in the new tangent plane.
Footprint propagate(const Footprint& fp, const Hit& next);

TexCoord texcoord_at(const Hit& h, const Footprint& fp);

// The hit as its material sees it, with texture coordinates filtered by fp, or without any (for
// a material that is not textured()).
inline ShadingPoint shading_point(const Hit& h, const Footprint& fp) {
  return {h.p, h.ng, h.ns, h.dpdu, h.dpdv, texcoord_at(h, fp)};
}
inline ShadingPoint shading_point(const Hit& h) { return {h.p, h.ng, h.ns, h.dpdu, h.dpdv, {}}; }

}  // namespace anamorph
