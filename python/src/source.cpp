#include <fmt/format.h>

#include "bindings.h"
#include "camera_handle.h"
#include "scene/scene_loader.h"

namespace anamorph::py {

namespace {
std::vector<std::string> joined(const std::vector<std::string>& a,
                                const std::vector<std::string>& b) {
  std::vector<std::string> r = a;
  r.insert(r.end(), b.begin(), b.end());
  return r;
}
}  // namespace

Scene SceneSource::load(const std::vector<std::string>& extra) const {
  const auto o = joined(overrides, extra);
  return path.empty() ? load_scene_from_string(text, name, o, frame) : load_scene(path, o, frame);
}

Scene SceneSource::load_view(const std::vector<std::string>& extra, const Scene& loaded) const {
  // Text sources are keyword cameras without geometry: loading them whole costs nothing more.
  if (path.empty()) return load(extra);
  return anamorph::load_view(path, joined(overrides, extra), frame, loaded);
}

CameraHandle::CameraHandle(SceneSource source, std::shared_ptr<const Scene> scene,
                           std::shared_ptr<const Scene> world)
    : source_(std::move(source)), scene_(std::move(scene)), world_(std::move(world)) {}

CameraHandle CameraHandle::from_text(const std::string& text, const std::string& name) {
  SceneSource s;
  s.text = text;
  s.name = name;
  auto scene = std::make_shared<const Scene>(s.load());
  return CameraHandle(std::move(s), std::move(scene), nullptr);
}

CameraHandle CameraHandle::resized(int width, int height) const {
  if (width < 1 || height < 1 || width > 65536 || height > 65536)
    throw std::invalid_argument(
        fmt::format("image size {}x{}: width and height must be 1..65536", width, height));
  if (width == this->width() && height == this->height()) return *this;
  const std::vector<std::string> size = {fmt::format("image.width={}", width),
                                         fmt::format("image.height={}", height)};
  auto scene =
      std::make_shared<const Scene>(world_ ? source_.load_view(size, *world_) : source_.load(size));
  return CameraHandle(source_, std::move(scene), world_);
}

}  // namespace anamorph::py
