// A loaded camera as the Python module holds it: the scene it was built in (which owns it and
// knows the image size) and where that came from, so the same camera can be rebuilt at another
// image size.
#pragma once

#include <memory>

#include "bindings.h"
#include "camera/virtual_camera.h"

namespace anamorph::py {

class CameraHandle {
 public:
  // `scene` holds the camera; `world` is the fully loaded scene a file's camera may take a model
  // camera (gltf_camera) from (null for keyword cameras, which load whole anyway).
  CameraHandle(SceneSource source, std::shared_ptr<const Scene> scene,
               std::shared_ptr<const Scene> world);
  // A camera from a scene's TOML text (the keyword front end writes one).
  static CameraHandle from_text(const std::string& text, const std::string& name);

  const VirtualCamera& camera() const { return *scene_->camera; }
  const Scene& scene() const { return *scene_; }
  int width() const { return scene_->render.width; }
  int height() const { return scene_->render.height; }
  // The same camera for a width x height image (presets depend on the aspect ratio).
  CameraHandle resized(int width, int height) const;

 private:
  SceneSource source_;
  std::shared_ptr<const Scene> scene_, world_;
};

}  // namespace anamorph::py
