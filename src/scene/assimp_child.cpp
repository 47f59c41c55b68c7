// The assimp loader's isolated half. Post-processing is chosen in assimp_loader.cpp's header
// comment; the parent reads the dump back without any.
#include "scene/assimp_child.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>
#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>

#include <cstdint>
#include <cstring>
#include <new>

#include "scene/loaders.h"

namespace anamorph {

std::vector<unsigned char> assimp_answer(const std::filesystem::path& file) {
  Assimp::Importer importer;
  const unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                         aiProcess_SortByPType | aiProcess_ValidateDataStructure;
  const aiScene* scene = importer.ReadFile(file.string(), flags);
  if (!scene) {
    // assimp catches its own allocation failures and reports them as text.
    if (std::strstr(importer.GetErrorString(), "bad_alloc")) throw std::bad_alloc();
    throw LoadError(importer.GetErrorString());
  }
  if (!scene->mRootNode || scene->mNumMeshes == 0) throw LoadError("contains no meshes");
  Assimp::Exporter exporter;
  const aiExportDataBlob* blob = exporter.ExportToBlob(scene, "assbin");
  if (!blob)
    throw LoadError(fmt::format("cannot hand the model over: {}", exporter.GetErrorString()));
  const auto* data = static_cast<const unsigned char*>(blob->data);
  std::vector<unsigned char> out(data, data + blob->size);
  const size_t dump = out.size();
  for (unsigned i = 0; i < scene->mNumMeshes; ++i) {
    const char* name = scene->mMeshes[i]->mName.C_Str();
    out.insert(out.end(), name, name + std::strlen(name) + 1);
  }
  const uint64_t names = out.size() - dump;
  const auto* n = reinterpret_cast<const unsigned char*>(&names);
  out.insert(out.end(), n, n + sizeof names);
  return out;
}

}  // namespace anamorph
