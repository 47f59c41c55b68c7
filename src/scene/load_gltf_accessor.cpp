#include "scene/load_gltf_accessor.h"

#include <algorithm>
#include <cstring>

#include <fmt/format.h>
#include <tiny_gltf.h>

#include "scene/loaders.h"

namespace anamorph {

namespace {

// One component at p, as a double (exact for every glTF component type).
double component(const unsigned char* p, int type, bool normalized) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      int8_t v;
      std::memcpy(&v, p, 1);
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return normalized ? p[0] / 255.0 : p[0];
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return normalized ? v / 4294967295.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_INT: {
      int32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
    default:
      return 0;
  }
}

// Bytes of bufferView `view` as [begin, begin + size), checked against its buffer.
const unsigned char* view_bytes(const tinygltf::Model& m, int view, size_t* size,
                                const std::string& what) {
  if (view < 0 || size_t(view) >= m.bufferViews.size())
    throw LoadError(fmt::format("{}: bufferView {} does not exist", what, view));
  const tinygltf::BufferView& bv = m.bufferViews[size_t(view)];
  if (bv.buffer < 0 || size_t(bv.buffer) >= m.buffers.size())
    throw LoadError(fmt::format("{}: bufferView {} names buffer {}, which does not exist", what,
                                view, bv.buffer));
  const auto& data = m.buffers[size_t(bv.buffer)].data;
  if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset)
    throw LoadError(
        fmt::format("{}: bufferView {} (offset {}, length {}) lies outside its "
                    "buffer of {} bytes",
                    what, view, bv.byteOffset, bv.byteLength, data.size()));
  *size = bv.byteLength;
  return data.data() + bv.byteOffset;
}

// All the bytes the file's buffers hold: an accessor without a bufferView (zeros, perhaps with
// sparse substitutions) may not have more elements than would fit in them. Its count is
// otherwise only a number: 400 bytes of JSON could ask for gigabytes of zeros.
size_t buffer_bytes(const tinygltf::Model& m) {
  size_t n = 0;
  for (const auto& b : m.buffers) n += b.data.size();
  return n;
}

// An accessor's element layout, checked against its declared type and the file's buffers.
struct AccessorLayout {
  const tinygltf::Accessor& a;
  int ncomp, csize;
  size_t elem;  // bytes per element
};

AccessorLayout accessor_layout(const tinygltf::Model& m, int index, int want_components,
                               const std::string& what) {
  if (index < 0 || size_t(index) >= m.accessors.size())
    throw LoadError(fmt::format("{}: does not exist ({} accessors)", what, m.accessors.size()));
  const tinygltf::Accessor& a = m.accessors[size_t(index)];
  const int ncomp = tinygltf::GetNumComponentsInType(uint32_t(a.type));
  const int csize = tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType));
  if (ncomp <= 0 || csize <= 0 || a.componentType == TINYGLTF_COMPONENT_TYPE_DOUBLE)
    throw LoadError(
        fmt::format("{}: unsupported type {} / componentType {}", what, a.type, a.componentType));
  if (ncomp != want_components)
    throw LoadError(fmt::format("{}: has {} components per element, expected {}", what, ncomp,
                                want_components));
  const size_t elem = size_t(ncomp) * size_t(csize);
  if (a.bufferView < 0 && a.count > buffer_bytes(m) / elem)
    throw LoadError(
        fmt::format("{}: {} elements without a bufferView are more than the file's buffers "
                    "({} bytes) could hold",
                    what, a.count, buffer_bytes(m)));
  return {a, ncomp, csize, elem};
}

// The elements stored in the accessor's bufferView (zero without one).
template <class F>
void for_each_dense(const tinygltf::Model& m, const AccessorLayout& l, const std::string& what,
                    F& f) {
  const tinygltf::Accessor& a = l.a;
  if (a.bufferView < 0) {
    for (size_t i = 0; i < a.count; ++i)
      for (int c = 0; c < l.ncomp; ++c) f(i, c, 0.0);
    return;
  }
  size_t size = 0;
  const unsigned char* base = view_bytes(m, a.bufferView, &size, what);
  // byteStride 0 (or absent) means tightly packed; tinygltf's ByteStride handles both.
  const int stride = a.ByteStride(m.bufferViews[size_t(a.bufferView)]);
  if (stride <= 0)
    throw LoadError(fmt::format("{}: invalid byteStride for its componentType", what));
  // Divided, not multiplied: a forged count must not wrap the product around.
  if (a.count > 0 && (a.byteOffset > size || size - a.byteOffset < l.elem ||
                      a.count - 1 > (size - a.byteOffset - l.elem) / size_t(stride)))
    throw LoadError(
        fmt::format("{}: {} elements at offset {} with stride {} overrun "
                    "bufferView {} ({} bytes)",
                    what, a.count, a.byteOffset, stride, a.bufferView, size));
  for (size_t i = 0; i < a.count; ++i) {
    const unsigned char* p = base + a.byteOffset + i * size_t(stride);
    for (int c = 0; c < l.ncomp; ++c)
      f(i, c, component(p + c * l.csize, a.componentType, a.normalized));
  }
}

// The sparse substitutions, each index and the bytes of both views checked.
template <class F>
void for_each_sparse(const tinygltf::Model& m, const AccessorLayout& l, const std::string& what,
                     F& f) {
  const tinygltf::Accessor& a = l.a;
  const auto& sp = a.sparse;
  if (sp.count < 0 || size_t(sp.count) > a.count)
    throw LoadError(fmt::format("{}: sparse count {} exceeds count {}", what, sp.count, a.count));
  const int isize = tinygltf::GetComponentSizeInBytes(uint32_t(sp.indices.componentType));
  if (isize <= 0 || sp.indices.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT)
    throw LoadError(fmt::format("{}: sparse indices have invalid componentType {}", what,
                                sp.indices.componentType));
  const size_t n = size_t(sp.count);
  size_t isz = 0, vsz = 0;
  const unsigned char* ib = view_bytes(m, sp.indices.bufferView, &isz, what + " sparse indices");
  const unsigned char* vb = view_bytes(m, sp.values.bufferView, &vsz, what + " sparse values");
  if (sp.indices.byteOffset < 0 || sp.values.byteOffset < 0 ||
      size_t(sp.indices.byteOffset) + n * size_t(isize) > isz ||
      size_t(sp.values.byteOffset) + n * l.elem > vsz)
    throw LoadError(fmt::format("{}: sparse data overruns its bufferViews", what));
  for (size_t k = 0; k < n; ++k) {
    const double di =
        component(ib + sp.indices.byteOffset + k * size_t(isize), sp.indices.componentType, false);
    const auto i = size_t(di);
    if (i >= a.count)
      throw LoadError(
          fmt::format("{}: sparse index {} out of range ({} elements)", what, i, a.count));
    const unsigned char* p = vb + sp.values.byteOffset + k * l.elem;
    for (int c = 0; c < l.ncomp; ++c)
      f(i, c, component(p + c * l.csize, a.componentType, a.normalized));
  }
}

// Calls f(element, component, value) for every component of every element, sparse substitutions
// applied. Elements not covered by a bufferView are zero. Every count is checked against the
// bytes present before f sees an element (callers allocate on the first call).
template <class F>
void for_each_component(const tinygltf::Model& m, int index, int want_components, F&& f) {
  const std::string what = fmt::format("accessor {}", index);
  const AccessorLayout l = accessor_layout(m, index, want_components, what);
  for_each_dense(m, l, what, f);
  if (l.a.sparse.isSparse) for_each_sparse(m, l, what, f);
}

}  // namespace

const unsigned char* buffer_view_bytes(const tinygltf::Model& m, int view, size_t* size,
                                       const std::string& what) {
  return view_bytes(m, view, size, what);
}

std::vector<float> read_accessor_floats(const tinygltf::Model& m, int index, int components) {
  std::vector<float> out;
  for_each_component(m, index, components, [&](size_t i, int c, double v) {
    // Sized at the first element, after for_each_component checked the count.
    if (out.empty()) out.resize(m.accessors[size_t(index)].count * size_t(components));
    out[i * size_t(components) + size_t(c)] = float(v);
  });
  return out;
}

std::vector<uint32_t> read_accessor_indices(const tinygltf::Model& m, int index) {
  if (index >= 0 && size_t(index) < m.accessors.size()) {
    const int ct = m.accessors[size_t(index)].componentType;
    if (ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
        ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT && ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
      throw LoadError(
          fmt::format("accessor {}: indices must be unsigned byte, short or int, "
                      "not componentType {}",
                      index, ct));
  }
  std::vector<uint32_t> out;
  for_each_component(m, index, 1, [&](size_t i, int, double v) {
    if (out.empty()) out.resize(m.accessors[size_t(index)].count);  // after the checks
    out[i] = uint32_t(v);
  });
  return out;
}

}  // namespace anamorph
