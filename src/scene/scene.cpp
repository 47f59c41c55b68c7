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

}  // namespace anamorph
