#include "scene/scene_pose.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <string>

#include "scene/gltf_animation.h"
#include "scene/gltf_lights.h"
#include "scene/skinning.h"
#include "scene/world_extent.h"

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

namespace {

void pose_at(Scene& s, double frame) {
  for (const SceneRig& r : s.rigs) {
    if (!animates(r)) continue;
    const RigPose pose = pose_rig(*r.rig, seconds(frame, s.fps));
    place_instances(s, r, pose);
    deform_meshes(s, r, pose);
    place_lights(s, r, pose);
  }
}

// The moving instances' transforms and the deforming meshes' vertices at the shutter's steps.
void pose_motion(Scene& s, double frame) {
  const std::vector<bool> moving = moving_instances(s), deforming = deforming_prototypes(s);
  const int n = s.motion_steps;
  for (int k = 0; k < n; ++k) {
    const double f = double(k) / (n - 1);
    pose_at(s, frame + s.shutter_open + (s.shutter_close - s.shutter_open) * f);
    for (size_t i = 0; i < s.instances.size(); ++i)
      if (moving[i]) s.instances[i].motion.push_back(s.instances[i].world_from_object);
    for (size_t p = 0; p < s.prototypes.size(); ++p) {
      if (!deforming[p]) continue;
      for (TriangleMesh& m : s.prototypes[p].meshes) {
        m.motion_positions.push_back(m.positions);
        if (!m.normals.empty()) m.motion_normals.push_back(m.normals);
      }
    }
  }
}

}  // namespace

bool object_motion_blur(const Scene& s) {
  return s.shutter_close > s.shutter_open && s.motion_steps >= 2 && gltf_moves_world(s);
}

void pose_scene(Scene& s, double frame) {
  for (Instance& inst : s.instances) inst.motion.clear();
  for (Prototype& p : s.prototypes)
    for (TriangleMesh& m : p.meshes) m.motion_positions.clear(), m.motion_normals.clear();
  if (object_motion_blur(s)) pose_motion(s, frame);
  pose_at(s, frame);
}

namespace {

// The entry of s.placed_objects for table `table` (null: not a mesh object).
PlacedObject* placed(Scene& s, int table) {
  for (PlacedObject& p : s.placed_objects)
    if (p.table == table) return &p;
  return nullptr;
}

// Why `to` cannot move the object `p` of `s` (empty: it can).
std::string placing_error(const Scene& s, const PlacedObject* p, const PlacedObject& to) {
  const std::string key = fmt::format("object.{}.transform", to.table);
  if (!p) return key + ": not a mesh object of the scene (only those move without a load)";
  if (p->moves_others)
    return key +
           ": the object brought lights or cameras of its model, which move only with a "
           "load (load the scene with this transform)";
  for (size_t k = 0; k < p->model_from_object.size(); ++k) {
    const Instance& inst = s.instances[p->first_instance + k];
    const std::string e = placement_error(to.transform * p->model_from_object[k],
                                          prototype_bounds(s.prototypes[inst.prototype]));
    if (!e.empty()) return key + ": " + e;
  }
  return "";
}

}  // namespace

bool place_objects(Scene& s, const std::vector<PlacedObject>& want) {
  std::vector<std::pair<PlacedObject*, const PlacedObject*>> moves;
  for (const PlacedObject& w : want) {
    PlacedObject* p = placed(s, w.table);
    if (p && p->transform.matrix() == w.transform.matrix()) continue;
    if (const std::string e = placing_error(s, p, w); !e.empty()) throw std::invalid_argument(e);
    moves.emplace_back(p, &w);
  }
  for (const auto& [p, w] : moves) {
    p->transform = w->transform;
    for (size_t k = 0; k < p->model_from_object.size(); ++k)
      s.instances[p->first_instance + k].world_from_object = p->transform * p->model_from_object[k];
    if (p->rig >= 0) s.rigs[size_t(p->rig)].world_from_model = p->transform;
  }
  if (!moves.empty() && has_gltf_animation(s)) pose_scene(s, s.frame);
  return !moves.empty();
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
