// Reading images back: an EXR's channels (what `anamorph render -o x.exr` and `anamorph rays`
// write) as float32 arrays, so Python code can compare with and reuse CLI output.
#include "bindings.h"
#include "io/image_io.h"

namespace anamorph::py {

void bind_image(pb::module_& m) {
  m.def(
      "read_exr_channels",
      [](const std::string& path) {
        int w = 0, h = 0;
        auto channels = read_exr_channels(path, &w, &h);
        pb::dict d;
        for (auto& [name, data] : channels) d[pb::str(name)] = to_array(std::move(data), {h, w});
        return d;
      },
      pb::arg("path"), "Every channel of an EXR by full name ('R', 'albedo.R', ...), (H, W).");
}

}  // namespace anamorph::py
