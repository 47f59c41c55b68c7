// From a hit and its material to a BSDF: texture lookups filtered by the ray footprint,
// normal mapping, and the mapping of both material models onto BSDF lobes.
#pragma once

#include "accel/accel.h"
#include "camera/camera.h"
#include "render/bsdf.h"
#include "scene/material.h"

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

// `wo` points away from the surface (toward the viewer). `albedo` receives the surface colour
// for the albedo AOV when not null.
Bsdf make_bsdf(const Material& m, const Hit& h, const Vec3& wo, const TexCoord& tc, Color* albedo);

}  // namespace anamorph
