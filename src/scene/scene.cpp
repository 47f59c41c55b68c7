#include "scene/scene.h"

namespace anamorph {

size_t Scene::triangle_count() const {
  size_t n = 0;
  for (const auto& p : prototypes)
    for (const auto& m : p.meshes) n += m.triangle_count();
  return n;
}

size_t Scene::instanced_triangle_count() const {
  size_t n = 0;
  for (const auto& inst : instances)
    for (const auto& m : prototypes[inst.prototype].meshes) n += m.triangle_count();
  return n;
}

std::shared_ptr<const FrameMotion> frame_motion(Scene&& other, const Scene* geometry) {
  const Scene& g = geometry ? *geometry : other;
  auto m = std::make_shared<FrameMotion>();
  m->frame = other.frame;
  for (const Instance& i : g.instances) m->instances.push_back(i.world_from_object);
  for (const AnalyticShape& s : g.shapes) m->shapes.push_back(s.world_from_object);
  m->camera = std::move(other.camera);
  if (geometry) return m;
  // (Its occlusion test asks where the objects are at that frame, not over its shutter.)
  for (Instance& i : other.instances) i.motion.clear();
  for (Prototype& p : other.prototypes)
    for (TriangleMesh& mesh : p.meshes) mesh.motion_positions.clear(), mesh.motion_normals.clear();
  m->geometry = std::make_shared<const Scene>(std::move(other));
  return m;
}

}  // namespace anamorph
