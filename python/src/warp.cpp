// anamorph._anamorph.warp: an image in a source projection reprojected through a camera, what
// `anamorph warp` writes (warp/warp_rows.h: the same pixels, the same filters), as an array.
#include <tbb/task_arena.h>

#include "bindings.h"
#include "camera/stmap.h"
#include "camera_handle.h"
#include "io/image_io.h"
#include "math/parallel.h"
#include "warp/warp_rows.h"

namespace anamorph::py {

namespace {

using Floats = pb::array_t<float, pb::array::c_style | pb::array::forcecast>;

// A path is read as the CLI reads its input (8-bit sRGB to linear); an array (H, W[, C]) with C
// in 1..4 is taken as linear values.
Image input_image(const pb::object& image, std::string* name) {
  if (pb::isinstance<pb::str>(image)) {
    *name = image.cast<std::string>();
    return read_image(*name);
  }
  const Floats a = Floats::ensure(image);
  if (!a || (a.ndim() != 2 && a.ndim() != 3))
    throw std::invalid_argument("image must be a path or an (H, W) or (H, W, C) array");
  const int channels = a.ndim() == 3 ? int(a.shape(2)) : 1;
  if (channels < 1 || channels > 4 || a.shape(0) < 1 || a.shape(1) < 1 || a.shape(0) > 65536 ||
      a.shape(1) > 65536)
    throw std::invalid_argument("image: 1 to 65536 rows and columns, 1 to 4 channels");
  Image img;
  img.height = int(a.shape(0)), img.width = int(a.shape(1)), img.channels = channels;
  img.pixels.assign(a.data(), a.data() + a.size());
  *name = "the image";
  return img;
}

pb::array_t<float> warp(const CameraHandle& c, const pb::object& image, const std::string& spec,
                        const std::string& filter, int threads) {
  const auto kind = texture_filter_named(filter);
  if (!kind) throw std::invalid_argument("filter " + filter + ": area, bilinear, aniso or bicubic");
  std::string name;
  Image img = input_image(image, &name);
  const auto source = make_source_projection(spec, double(img.width) / img.height);
  check_source_aspect(*source, img.width, img.height, name);
  const Camera& cam = c.camera();
  const int W = c.width(), H = c.height();
  std::vector<float> rgba;
  {
    pb::gil_scoped_release release;
    central_origin(cam, W, H);
    tbb::task_arena arena(arena_concurrency(threads));
    arena.execute([&] {
      const auto texture = make_warp_texture(std::move(img), source->wraps_u(), *kind, threads);
      rgba = warp_image({cam, *source, *texture, W, H});
    });
  }
  return to_array(std::move(rgba), {H, W, 4});
}

}  // namespace

void bind_warp(pb::module_& m) {
  m.def("warp", &warp, pb::arg("camera"), pb::arg("image"), pb::arg("source"), pb::arg("filter"),
        pb::arg("threads"));
}

}  // namespace anamorph::py
