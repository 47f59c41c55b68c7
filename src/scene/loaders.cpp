#include "scene/loaders.h"

#include "camera/org_mesh.h"
#include "camera/table_functions.h"
#include "io/image_io.h"
#include "io/read_log.h"
#include "math/user_text.h"
#include "scene/load_common.h"

namespace anamorph {

namespace {

// The mesh origin function (camera/) reads its file through this: camera/ sits below the
// loaders and cannot call them itself.
void read_mesh_file(const std::string& file, std::vector<Prototype>* prototypes,
                    std::vector<Instance>* instances) {
  const ReadRole role("the camera's origin mesh");
  LoadedModel m = load_model(file);
  *prototypes = std::move(m.prototypes);
  *instances = std::move(m.instances);
}

// The table functions (camera/) read their EXR through this. A layer L is L.X, L.Y, L.Z, plus
// L_lo.X/Y/Z when present: float residuals that `anamorph rays` writes so that hi + lo carries a
// double to ~1e-15 (EXR has no 64-bit floats); validity is valid.V when present.
RayTableData read_ray_table(const std::string& file, const std::string& layer) {
  RayTableData d;
  const ReadRole role("a ray table");
  const auto ch = read_exr_channels(file, &d.width, &d.height);
  const auto plane = [&](const std::string& name) -> const std::vector<float>* {
    const auto it = ch.find(name);
    return it == ch.end() ? nullptr : &it->second;
  };
  const std::vector<float>* xyz[3] = {plane(layer + ".X"), plane(layer + ".Y"),
                                      plane(layer + ".Z")};
  if (!xyz[0] || !xyz[1] || !xyz[2]) {
    std::string have;
    for (const auto& [name, values] : ch) have += (have.empty() ? "" : ", ") + name;
    throw std::runtime_error(file + ": no layer '" + layer + "' (channels " + layer + ".X, .Y, " +
                             ".Z); the file has " + have);
  }
  const std::vector<float>* lo[3] = {plane(layer + "_lo.X"), plane(layer + "_lo.Y"),
                                     plane(layer + "_lo.Z")};
  const size_t n = size_t(d.width) * size_t(d.height);
  d.values.resize(n);
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c)
      d.values[i][c] = double((*xyz[c])[i]) + (lo[c] ? double((*lo[c])[i]) : 0.0);
  if (const auto* valid = plane("valid.V"))
    for (size_t i = 0; i < n; ++i) d.valid.push_back((*valid)[i] != 0);
  return d;
}

[[maybe_unused]] const bool kMeshReaderInstalled = [] {
  set_mesh_file_reader(&read_mesh_file);
  set_ray_table_file_reader(&read_ray_table);
  return true;
}();

}  // namespace

LoadedModel load_model(const std::filesystem::path& file) {
  // (The assimp child gets the name through argv, where a NUL would end it.)
  if (has_nul(file.native())) throw LoadError(nul_in_path_message(file.native()));
  const std::string ext = lowercase_extension(file);
  if (ext == ".gltf" || ext == ".glb") return load_gltf(file);
  return load_with_assimp(file);
}

}  // namespace anamorph
