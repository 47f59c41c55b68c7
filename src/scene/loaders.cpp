#include "scene/loaders.h"

#include "camera/org_mesh.h"
#include "scene/load_common.h"

namespace anamorph {

namespace {

// The mesh origin function (camera/) reads its file through this: camera/ sits below the
// loaders and cannot call them itself.
void read_mesh_file(const std::string& file, std::vector<Prototype>* prototypes,
                    std::vector<Instance>* instances) {
  LoadedModel m = load_model(file);
  *prototypes = std::move(m.prototypes);
  *instances = std::move(m.instances);
}

[[maybe_unused]] const bool kMeshReaderInstalled = [] {
  set_mesh_file_reader(&read_mesh_file);
  return true;
}();

}  // namespace

LoadedModel load_model(const std::filesystem::path& file) {
  const std::string ext = lowercase_extension(file);
  if (ext == ".gltf" || ext == ".glb") return load_gltf(file);
  return load_with_assimp(file);
}

}  // namespace anamorph
