// The model loaders from bytes: glTF (text and binary), OBJ, PLY and STL through load_model
// (assimp in its limited child process). FUZZ_MODEL_EXTENSION selects the format at build time.
#include "fuzz_util.h"
#include "scene/loaders.h"

using namespace anamorph;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > 1 << 20) return 0;
  const fuzz::TempFile f(data, size, FUZZ_MODEL_EXTENSION);
  try {
    const LoadedModel m = load_model(f.path());
    (void)m.triangle_count();
  } catch (const LoadError&) {
  }
  return 0;
}
