// The assimp loader's isolated half. Post-processing is chosen in assimp_loader.cpp's header
// comment; the parent reads the dump back without any.
#include "scene/assimp_child.h"

#include <assimp/MemoryIOWrapper.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>
#include <assimp/Exporter.hpp>
#include <assimp/IOSystem.hpp>
#include <assimp/Importer.hpp>

#include <cstdint>
#include <cstring>
#include <new>
#include <string_view>
#include <variant>

#include "io/read_file.h"
#include "scene/loaders.h"

namespace anamorph {

namespace {

// assimp opens the model and the files it names (an OBJ's material library, a glTF 1 buffer)
// through this: each read whole by io/read_file.h, so a FIFO, a device or a directory is refused
// at once and nothing is larger than a model may be (assimp's own reader would read /dev/zero
// until its memory limit, or wait on a FIFO until its clock ran out), and the editor's confinement
// applies (the loader program installs it).
// The files it opened are listed in the answer, so the parent can record them as the run's
// inputs (an output must not overwrite an OBJ's material library).
class InputIOSystem : public Assimp::IOSystem {
 public:
  explicit InputIOSystem(std::vector<std::string>* opened) : opened_(opened) {}
  bool Exists(const char* file) const override {
    const auto opened = open_input(file, kModelInput);
    const auto* failure = std::get_if<ReadFailure>(&opened);
    return !failure || failure->error != ENOENT;
  }
  char getOsSeparator() const override { return '/'; }
  Assimp::IOStream* Open(const char* file, const char* mode) override {
    if (std::string_view(mode).find_first_of("wa+") != std::string_view::npos) return nullptr;
    std::vector<unsigned char> bytes;
    if (read_whole_file(file, &bytes, kModelInput)) return nullptr;
    opened_->push_back(file);
    auto* copy = new uint8_t[bytes.size() + 1];
    std::memcpy(copy, bytes.data(), bytes.size());
    return new Assimp::MemoryIOStream(copy, bytes.size(), true);
  }
  void Close(Assimp::IOStream* stream) override { delete stream; }

 private:
  std::vector<std::string>* opened_;
};

// Appends `strings`, each ending in a NUL, and their byte count (8 bytes, native order).
void append_strings(std::vector<unsigned char>& out, const std::vector<std::string>& strings) {
  const size_t start = out.size();
  for (const std::string& s : strings) out.insert(out.end(), s.c_str(), s.c_str() + s.size() + 1);
  const uint64_t bytes = out.size() - start;
  const auto* n = reinterpret_cast<const unsigned char*>(&bytes);
  out.insert(out.end(), n, n + sizeof bytes);
}

}  // namespace

std::vector<unsigned char> assimp_answer(const std::filesystem::path& file) {
  std::vector<std::string> opened;
  Assimp::Importer importer;
  importer.SetIOHandler(new InputIOSystem(&opened));  // (the importer owns it)
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
  std::vector<std::string> names;
  for (unsigned i = 0; i < scene->mNumMeshes; ++i)
    names.push_back(scene->mMeshes[i]->mName.C_Str());
  append_strings(out, names);
  append_strings(out, opened);
  return out;
}

}  // namespace anamorph
