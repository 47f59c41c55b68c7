// Reading glTF accessors into plain arrays: any component type, normalized integers, byteStride
// (including 0 = tightly packed), accessors without a bufferView (zeros) and sparse accessors.
// Every read is bounds-checked against its bufferView and buffer.
#pragma once

#include <cstdint>
#include <vector>

namespace tinygltf {
class Model;
}

namespace anamorph {

// Accessor `index` as floats, `components` per element (the accessor must have exactly that
// many). Normalized integers map to [0,1] / [-1,1]; other integers convert as they are
// (KHR_mesh_quantization). Throws LoadError("accessor N: ...") on any inconsistency.
std::vector<float> read_accessor_floats(const tinygltf::Model& model, int index, int components);

// Index accessor: SCALAR of unsigned byte, short or int.
std::vector<uint32_t> read_accessor_indices(const tinygltf::Model& model, int index);

}  // namespace anamorph
