// The Python module `anamorph._anamorph`: the C++ library behind the `anamorph` package
// (python/anamorph/), which adds the keyword-argument front end. Each bind_* registers one part.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace anamorph::py {

namespace pb = pybind11;

// Where a scene comes from: a file, or TOML text (the Camera(...) keyword front end), each with
// `--set`-style overrides ("dotted.key=value") and an animation frame.
struct SceneSource {
  std::string path;  // a scene file; empty: `text`
  std::string text;
  std::string name;  // `text`'s name in messages ("<anamorph.Camera>"); relative paths: cwd
  std::vector<std::string> overrides;
  double frame = 0;

  // The whole scene with `extra` overrides after the source's own.
  Scene load(const std::vector<std::string>& extra = {}) const;
  // Only what changes the view ([image], [render], [camera]); geometry from `loaded`.
  Scene load_view(const std::vector<std::string>& extra, const Scene& loaded) const;
};

// A float64 / uint8 array of `shape` that owns `data` (moved, no copy).
template <class T>
pb::array_t<T> to_array(std::vector<T>&& data, std::vector<pb::ssize_t> shape) {
  auto* owned = new std::vector<T>(std::move(data));
  pb::capsule free(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return pb::array_t<T>(shape, owned->data(), free);
}

// Raises Python's MemoryError with `message` (a C++ exception pybind11 turns into it).
[[noreturn]] void raise_memory_error(const std::string& message);

void bind_errors(pb::module_& m);
void bind_schema(pb::module_& m);
void bind_camera(pb::module_& m);
void bind_scene(pb::module_& m);
void bind_image(pb::module_& m);
void bind_warp(pb::module_& m);
void bind_solve(pb::module_& m);

}  // namespace anamorph::py
