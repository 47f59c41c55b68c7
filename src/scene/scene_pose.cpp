#include "scene/scene_pose.h"

#include <algorithm>

#include "scene/gltf_animation.h"
#include "scene/gltf_lights.h"
#include "scene/skinning.h"

namespace anamorph {

namespace {

bool animates(const SceneRig& r) { return r.animate && r.rig && r.rig->animated(); }

double seconds(double frame, double fps) { return frame / fps; }

// What the pose at one time gives the instances and deforming meshes.
void place_instances(Scene& s, const SceneRig& r, const RigPose& pose) {
  const GltfRig& rig = *r.rig;
  for (size_t i = 0; i < rig.instance_nodes.size(); ++i) {
    if (rig.instance_skinned[i]) continue;  // (placed by its skin, in model space)
    const int node = rig.instance_nodes[i];
    if (!rig.moving[size_t(node)]) continue;
    s.instances[r.first_instance + i].world_from_object =
        r.world_from_model * Transform(pose.world[size_t(node)]);
  }
}

void deform_meshes(Scene& s, const SceneRig& r, const RigPose& pose) {
  for (const Deformer& d : r.rig->deformers)
    deform(*r.rig, d, pose, s.prototypes[r.first_prototype + d.prototype].meshes);
}

void place_lights(Scene& s, const SceneRig& r, const RigPose& pose) {
  if (r.first_light < 0) return;
  const GltfRig& rig = *r.rig;
  for (size_t i = 0; i < rig.light_nodes.size(); ++i) {
    const int node = rig.light_nodes[i];
    if (!rig.moving[size_t(node)]) continue;
    place_light(s.lights[size_t(r.first_light) + i],
                r.world_from_model * Transform(pose.world[size_t(node)]));
  }
}

}  // namespace

bool has_gltf_animation(const Scene& s) {
  return std::any_of(s.rigs.begin(), s.rigs.end(), animates);
}

bool gltf_moves_world(const Scene& s) {
  return std::any_of(s.rigs.begin(), s.rigs.end(), [](const SceneRig& r) {
    if (!animates(r)) return false;
    const GltfRig& rig = *r.rig;
    const auto moving = [&](int node) { return bool(rig.moving[size_t(node)]); };
    return !rig.deformers.empty() ||
           std::any_of(rig.instance_nodes.begin(), rig.instance_nodes.end(), moving) ||
           (r.first_light >= 0 &&
            std::any_of(rig.light_nodes.begin(), rig.light_nodes.end(), moving));
  });
}

std::vector<bool> moving_instances(const Scene& s) {
  std::vector<bool> moving(s.instances.size(), false);
  for (const SceneRig& r : s.rigs) {
    if (!animates(r)) continue;
    const GltfRig& rig = *r.rig;
    for (size_t i = 0; i < rig.instance_nodes.size(); ++i)
      if (!rig.instance_skinned[i] && rig.moving[size_t(rig.instance_nodes[i])] &&
          r.first_instance + i < moving.size())
        moving[r.first_instance + i] = true;
  }
  return moving;
}

std::vector<bool> deforming_prototypes(const Scene& s) {
  std::vector<bool> deforming(s.prototypes.size(), false);
  for (const SceneRig& r : s.rigs) {
    if (!animates(r)) continue;
    for (const Deformer& d : r.rig->deformers)
      if (r.first_prototype + d.prototype < deforming.size())
        deforming[r.first_prototype + d.prototype] = true;
  }
  return deforming;
}

std::pair<double, double> gltf_frame_range(const Scene& s) {
  bool any = false;
  double a = 0, b = 0;
  for (const SceneRig& r : s.rigs) {
    if (!animates(r)) continue;
    a = any ? std::min(a, r.rig->start) : r.rig->start;
    b = any ? std::max(b, r.rig->end) : r.rig->end;
    any = true;
  }
  return {a * s.fps, b * s.fps};
}

void pose_scene(Scene& s, double frame) {
  for (const SceneRig& r : s.rigs) {
    if (!animates(r)) continue;
    const RigPose pose = pose_rig(*r.rig, seconds(frame, s.fps));
    place_instances(s, r, pose);
    deform_meshes(s, r, pose);
    place_lights(s, r, pose);
  }
}

void pose_model_cameras(const std::vector<SceneRig>& rigs, double fps, double frame,
                        std::vector<ModelCamera>& cameras) {
  for (const SceneRig& r : rigs) {
    if (!animates(r) || r.first_camera < 0) continue;
    const RigPose pose = pose_rig(*r.rig, seconds(frame, fps));
    const GltfRig& rig = *r.rig;
    for (size_t i = 0; i < rig.camera_nodes.size(); ++i) {
      const size_t at = size_t(r.first_camera) + i;
      if (at < cameras.size())
        cameras[at].world_from_camera =
            r.world_from_model * Transform(pose.world[size_t(rig.camera_nodes[i])]);
    }
  }
}

}  // namespace anamorph
