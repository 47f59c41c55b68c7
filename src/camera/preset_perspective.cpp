// perspective: org = point (the eye), dir = plane (the image plane at distance 1).
#include <cmath>

#include "camera/dir_basic.h"
#include "camera/org_basic.h"
#include "camera/preset_list.h"
#include "camera/preset_util.h"

namespace anamorph {

namespace {

const std::string_view kFovAxes[] = {"horizontal", "vertical", "diagonal"};

const ParamSpec kParams[] = {
    ANAMORPH_LOOK_AT_PARAMS,
    {.name = "fov",
     .type = ParamType::Number,
     .default_value = "60",
     .doc = "Field of view in degrees, measured along fov_axis.",
     .min = 0,
     .max = 180,
     .min_exclusive = true,
     .max_exclusive = true,
     .unit = "degrees"},
    {"fov_axis", ParamType::String, "\"horizontal\"", "Which image extent `fov` spans.", -kInf,
     kInf, kFovAxes},
    {"lens_shift", ParamType::Vec2, "[0, 0]",
     "Off-axis shift of the image window, in units of the image width and height (as a view "
     "camera's rise and shift; +x right, +y up)."},
};

VirtualCameraParts create(const ParamValues& v, const ImageInfo& img) {
  check_params(kParams, v);
  // Image plane window at distance 1: width w, height h, centered at (cx, cy, -1).
  const Vec2 half = window_half_extent(std::tan(radians(v.number("fov")) * 0.5),
                                       v.string("fov_axis"), img.aspect());
  const double w = 2 * half.x, h = 2 * half.y;
  const Vec2 shift = v.vec2("lens_shift");
  const Vec3 center{shift.x * w, shift.y * h, -1};
  VirtualCameraParts p;
  p.org = make_point_org({0, 0, 0});
  p.dir = make_surface_dir(make_plane_org(center, {w, 0, 0}, {0, -h, 0}), {0, 0, 0});
  p.world_from_camera = rig_from_look_at(v);
  p.derivatives.rig = look_at_rig_derivative(v);
  // fov: the window's extents are t = tan(fov / 2) times constants, so the unnormalized direction
  // q = dir / -dir.z on the plane z = -1 moves by (q.x, q.y, 0) dt / t.
  const double t = std::tan(radians(v.number("fov")) * 0.5);
  p.derivatives.ray = [t](std::string_view key, const CameraRay& r, Vec3* dorg, Vec3* ddir) {
    if (key != "fov" || !(r.dir.z < 0)) return false;
    const Vec3 q = r.dir / -r.dir.z;
    const Vec3 dq = Vec3{q.x, q.y, 0} * ((1 + t * t) * (kPi / 360) / t);
    *dorg = {};
    *ddir = (dq - r.dir * dot(r.dir, dq)) / length(q);
    return true;
  };
  p.description = "perspective (org point + dir plane)";
  // Central projection onto z = -1, then the window.
  p.inverse = make_inverse([w, h, center](const Vec3& q) -> std::vector<Vec2> {
    if (!(q.z < 0)) return {};
    Vec2 uv{0.5 + (q.x / -q.z - center.x) / w, 0.5 - (q.y / -q.z - center.y) / h};
    if (!clamp_to_image(&uv)) return {};
    return {uv};
  });
  return p;
}

}  // namespace

const PresetInfo kPerspectivePreset{
    "perspective",
    "The pinhole camera: org = point (the eye), dir = plane at distance 1 through the image.",
    kParams, create};

}  // namespace anamorph
