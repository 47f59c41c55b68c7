// orthographic: org = plane (the film, view_width wide), dir = constant (the view direction).
#include "camera/dir_basic.h"
#include "camera/org_basic.h"
#include "camera/preset_list.h"
#include "camera/preset_util.h"

namespace anamorph {

namespace {

const ParamSpec kParams[] = {
    ANAMORPH_LOOK_AT_PARAMS,
    {.name = "view_width",
     .type = ParamType::Number,
     .default_value = "2",
     .doc = "Width of the viewed rectangle in world units; its height is view_width / aspect. The "
            "rectangle is centered on look_from and perpendicular to the view direction; rays "
            "start on "
            "it.",
     .min = 0,
     .min_exclusive = true,
     .unit = "scene units"},
};

VirtualCameraParts create(const ParamValues& v, const ImageInfo& img) {
  check_params(kParams, v);
  const double w = v.number("view_width"), h = w / img.aspect();
  VirtualCameraParts p;
  p.org = make_plane_org({0, 0, 0}, {w, 0, 0}, {0, -h, 0});
  p.dir = make_constant_dir({0, 0, -1});
  p.world_from_camera = rig_from_look_at(v);
  p.description = "orthographic (org plane + dir constant)";
  // Parallel projection onto the film; only points in front of it are seen.
  p.inverse = make_inverse([w, h](const Vec3& q) -> std::vector<Vec2> {
    if (!(q.z < 0)) return {};
    Vec2 uv{0.5 + q.x / w, 0.5 - q.y / h};
    if (!clamp_to_image(&uv)) return {};
    return {uv};
  });
  return p;
}

}  // namespace

const PresetInfo kOrthographicPreset{
    "orthographic",
    "Parallel projection: org = plane (a view_width-wide rectangle through look_from), "
    "dir = constant (look_at - look_from).",
    kParams, create};

}  // namespace anamorph
