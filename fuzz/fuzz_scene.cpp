// The whole scene load from TOML text up to a built camera and acceleration structure, and a few
// rays of that camera: a bad scene must be a SceneError, every ray finite with a unit direction.
#include <cmath>
#include <cstdlib>

#include "accel/accel.h"
#include "fuzz_util.h"
#include "scene/scene_loader.h"
#include "scene/toml_reader.h"

using namespace anamorph;

// Every ray the camera gives is finite with a unit direction (or there is no ray).
void check_rays(const Camera& cam) {
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 5; ++i) {
      CameraSample s;
      s.uv = {(i + 0.5) / 5, (j + 0.5) / 5};
      const auto r = cam.generate(s);
      if (!r) continue;
      if (!is_finite(r->org) || !is_finite(r->dir) || std::abs(length(r->dir) - 1) > 1e-6)
        std::abort();
    }
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > 64 * 1024) return 0;
  Scene scene;
  try {
    scene = load_scene_from_string(fuzz::text(data, size), "fuzz.toml");
  } catch (const SceneError&) {
    return 0;
  }
  // Keep runs short: big images are fine to load but not to probe pixel by pixel here.
  check_rays(*scene.camera);
  const Accel accel(scene);
  return 0;
}
