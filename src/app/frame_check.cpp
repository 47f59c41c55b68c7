#include "app/frame_check.h"

#include "scene/scene_loader.h"

namespace anamorph::app {

void check_frames(const SceneOptions& o, const std::vector<std::string>& extra, int first, int last,
                  const Scene& loaded) {
  // Without [[animate]] entries every frame reads as `loaded` did.
  if (loaded.animated.empty()) return;
  std::vector<std::string> overrides = o.overrides();
  overrides.insert(overrides.end(), extra.begin(), extra.end());
  for (int f = first; f <= last; ++f) check_scene_frame(o.scene, overrides, f, loaded);
}

}  // namespace anamorph::app
