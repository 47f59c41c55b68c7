// Multiperspective cameras whose rays pass through two lines instead of one point.
// pushbroom (linear pushbroom, Gupta & Hartley 1997): a line sensor swept along the right
//   vector; each column is a vertical 1-D perspective view. org = segment along u (the path),
//   dir = segment along v (the sensor line at distance 1): parallel across u, perspective down v.
// crossed_slits (Zomet et al. 2003): every ray meets a vertical slit through look_from and a
//   horizontal slit at slit_distance ahead. For image-plane slopes (a, b), with depth t ahead:
//   x = a t, y = b (t - slit_distance). org = segment along v on the vertical slit
//   (y = -b slit_distance), dir = plane (a, b, -1). slit_distance = 0 is the perspective camera.
#include <cmath>

#include "camera/dir_basic.h"
#include "camera/org_basic.h"
#include "camera/preset_list.h"
#include "camera/preset_util.h"

namespace anamorph {

namespace {

// --- pushbroom -------------------------------------------------------------------------------

const ParamSpec kPushbroomParams[] = {
    ANAMORPH_LOOK_AT_PARAMS,
    {.name = "fov",
     .type = ParamType::Number,
     .default_value = "60",
     .doc = "Vertical field of view of the line sensor in degrees.",
     .min = 0,
     .max = 180,
     .min_exclusive = true,
     .max_exclusive = true,
     .unit = "degrees"},
    {.name = "length",
     .type = ParamType::Number,
     .default_value = "none",
     .doc = "Length of the sensor's path along the right vector, in world units, centered on "
            "look_from. Default: square pixels at distance 1 (2 tan(fov/2) * aspect).",
     .min = 0,
     .min_exclusive = true,
     .unit = "scene units"},
};

VirtualCameraParts create_pushbroom(const ParamValues& v, const ImageInfo& img) {
  check_params(kPushbroomParams, v);
  const double bh = std::tan(radians(v.number("fov")) / 2);  // half height at distance 1
  const double len = v.has("length") ? v.number("length") : 2 * bh * img.aspect();
  VirtualCameraParts p;
  p.org = make_segment_org({}, {len, 0, 0}, false);
  p.dir = make_surface_dir(make_segment_org({0, 0, -1}, {0, -2 * bh, 0}, true), {});
  p.world_from_camera = rig_from_look_at(v);
  p.description = "pushbroom (org segment along u + dir segment along v)";
  p.inverse = make_inverse([len, bh](const Vec3& q) -> std::vector<Vec2> {
    if (!(q.z < 0)) return {};
    Vec2 uv{0.5 + q.x / len, 0.5 - q.y / -q.z / (2 * bh)};
    if (!clamp_to_image(&uv)) return {};
    return {uv};
  });
  return p;
}

// --- crossed_slits ---------------------------------------------------------------------------

const ParamSpec kCrossedSlitsParams[] = {
    ANAMORPH_LOOK_AT_PARAMS,
    {.name = "fov",
     .type = ParamType::Number,
     .default_value = "60",
     .doc = "Horizontal field of view in degrees, seen from the vertical slit; the vertical extent "
            "follows from the aspect (seen from the horizontal slit).",
     .min = 0,
     .max = 180,
     .min_exclusive = true,
     .max_exclusive = true,
     .unit = "degrees"},
    {"slit_distance", ParamType::Number, "1",
     "Distance of the horizontal slit ahead of the vertical slit through look_from, in world "
     "units (negative: behind it; 0: a pinhole)."},
};

VirtualCameraParts create_crossed_slits(const ParamValues& v, const ImageInfo& img) {
  check_params(kCrossedSlitsParams, v);
  const double ah = std::tan(radians(v.number("fov")) / 2), bh = ah / img.aspect();
  const double th = v.number("slit_distance");
  VirtualCameraParts p;
  // y at the vertical slit: -b th, with b = (1 - 2v) bh.
  p.org = make_segment_org({}, {0, 2 * bh * th, 0}, true);
  p.dir = make_surface_dir(make_plane_org({0, 0, -1}, {2 * ah, 0, 0}, {0, -2 * bh, 0}), {});
  p.world_from_camera = rig_from_look_at(v);
  p.description = "crossed slits (org segment on the vertical slit + dir plane)";
  p.inverse = make_inverse([ah, bh, th](const Vec3& q) -> std::vector<Vec2> {
    const double t = -q.z;
    if (!(t > 0) || !(std::abs(t - th) > 0)) return {};
    Vec2 uv{0.5 + q.x / t / (2 * ah), 0.5 - q.y / (t - th) / (2 * bh)};
    if (!clamp_to_image(&uv)) return {};
    return {uv};
  });
  return p;
}

}  // namespace

const PresetInfo kPushbroomPreset{
    "pushbroom",
    "Linear pushbroom: perspective down each column, parallel across columns (a line sensor "
    "moved along the right vector). org = segment, dir = segment.",
    kPushbroomParams, create_pushbroom};

const PresetInfo kCrossedSlitsPreset{
    "crossed_slits",
    "Crossed-slits projection: every ray passes a vertical slit at look_from and a horizontal "
    "slit slit_distance ahead. org = segment on the vertical slit, dir = plane.",
    kCrossedSlitsParams, create_crossed_slits};

}  // namespace anamorph
