#include "scene/loaders.h"

#include "scene/load_common.h"

namespace anamorph {

LoadedModel load_model(const std::filesystem::path& file) {
  const std::string ext = lowercase_extension(file);
  if (ext == ".gltf" || ext == ".glb") return load_gltf(file);
  return load_with_assimp(file);
}

}  // namespace anamorph
