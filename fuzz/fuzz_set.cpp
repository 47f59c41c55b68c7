// --set overrides: the first line of the input is KEY=VALUE, applied to a small scene with every
// kind of table (arrays of tables addressed by index included).
#include "fuzz_util.h"
#include "scene/scene_loader.h"
#include "scene/toml_reader.h"

using namespace anamorph;

namespace {
const char* kScene = R"(
[image]
width = 8
height = 6
[render]
spp = 2
[camera]
preset = "fisheye"
fov = 180
[[camera.coin]]
position = [0, 0, -3]
[[material]]
name = "m"
color = { type = "checker", scale = 0.5 }
[[object]]
type = "sphere"
material = "m"
[[object]]
type = "box"
size = [1, 2, 3]
[[light]]
type = "spot"
position = [1, 2, 3]
[environment]
color = 0.2
)";
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > 4096) return 0;
  std::string text = fuzz::text(data, size);
  std::vector<std::string> overrides;
  for (size_t s = 0; s <= text.size() && overrides.size() < 4;) {
    size_t e = text.find('\n', s);
    if (e == std::string::npos) e = text.size();
    overrides.push_back(text.substr(s, e - s));
    s = e + 1;
  }
  try {
    load_scene_from_string(kScene, "fuzz.toml", overrides);
  } catch (const SceneError&) {
  }
  return 0;
}
