// Camera functions, presets and coins from arbitrary parameter tables (the input is the body of
// a [camera] table), evaluated at random image positions, alone and as packets: every ray
// finite with a unit direction, or no ray; packets give the bits of single rays.
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "fuzz_util.h"
#include "math/rng.h"
#include "scene/scene_loader.h"
#include "scene/toml_reader.h"

using namespace anamorph;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > 16 * 1024) return 0;
  Scene scene;
  try {
    scene = load_scene_from_string(
        "[image]\nwidth = 16\nheight = 12\n[camera]\n" + fuzz::text(data, size), "fuzz.toml");
  } catch (const SceneError&) {
    return 0;
  }
  const Camera& cam = *scene.camera;
  Rng rng(size, 7);
  CameraSample samples[kCameraBatch];
  for (CameraSample& s : samples) s.uv = {rng.uniform(), rng.uniform()};
  CameraRayBatch batch;
  cam.generate_batch(samples, kCameraBatch, &batch);
  for (int i = 0; i < kCameraBatch; ++i) {
    const auto r = cam.generate(samples[i]);
    if (bool(r) != batch.valid[i]) std::abort();
    if (!r) continue;
    if (!is_finite(r->org) || !is_finite(r->dir) || std::abs(length(r->dir) - 1) > 1e-6)
      std::abort();
    const CameraRay b = batch.ray(i);
    if (std::memcmp(&b, &*r, sizeof b) != 0 && !cam.uses_lens_or_time()) std::abort();
  }
  return 0;
}
