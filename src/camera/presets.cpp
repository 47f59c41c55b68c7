#include "camera/presets.h"

#include <vector>

#include "camera/preset_list.h"

namespace anamorph {

Transform rig_from_look_at(const ParamValues& v) {
  const Vec3 from = v.vec3("look_from"), at = v.vec3("look_at"), up = v.vec3("up");
  if (!(length(at - from) > 0)) throw ParamError("look_at", "look_at must differ from look_from");
  if (!(length(cross(at - from, up)) > 1e-12 * length(at - from) * length(up)))
    throw ParamError("up", "up must not be parallel to the viewing direction (look_at - look_from)");
  return Transform::look_at(from, at, up);
}

std::span<const PresetInfo> camera_presets() {
  static const std::vector<PresetInfo> list = {kPerspectivePreset};
  return list;
}

const PresetInfo* find_preset(std::string_view name) {
  for (const auto& p : camera_presets())
    if (p.name == name) return &p;
  return nullptr;
}

}  // namespace anamorph
