// Reading glTF accessors into plain arrays: any component type, normalized integers, byteStride
// (including 0 = tightly packed), accessors without a bufferView (zeros) and sparse accessors.
// Every read is bounds-checked against its bufferView and buffer.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace tinygltf {
class Model;
}

namespace anamorph {

// Accessor `index` as floats, `components` per element (the accessor must have exactly that
// many). Normalized integers map to [0,1] / [-1,1]; other integers convert as they are
// (KHR_mesh_quantization). Throws LoadError("accessor N: ...") on any inconsistency.
std::vector<float> read_accessor_floats(const tinygltf::Model& model, int index, int components);

// The bytes of bufferView `view` ([result, result + *size)), checked to lie inside its buffer;
// throws LoadError naming `what` otherwise.
const unsigned char* buffer_view_bytes(const tinygltf::Model& model, int view, size_t* size,
                                       const std::string& what);

// Index accessor: SCALAR of unsigned byte, short or int.
std::vector<uint32_t> read_accessor_indices(const tinygltf::Model& model, int index);

}  // namespace anamorph
