// The image readers from bytes: PNG, JPEG, BMP, TGA, HDR (stb_image) and EXR (tinyexr), chosen
// by content as for textures; a bad image must be an ImageReadError.
#include "fuzz_util.h"
#include "io/image_io.h"

using namespace anamorph;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > 1 << 20) return 0;
  const fuzz::TempFile f(data, size, ".img");
  try {
    const Image img = read_image(f.path());
    (void)img.pixels.size();
  } catch (const ImageReadError&) {
  }
  return 0;
}
