// Helpers for the loader tests: a per-test scratch directory, and a writer for small glTF files
// with data-URI buffers so each test states the exact bytes it feeds the loader.
#pragma once

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include "scene/loaders.h"

namespace anamorph::test {

// A fresh directory for the running test, removed at the end.
class ScratchDir {
 public:
  ScratchDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            ("anamorph_" + std::string(info->test_suite_name()) + "_" + info->name() + "_" +
             std::to_string(::getpid()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path write(const std::string& name, const std::string& bytes) const {
    const auto p = path_ / name;
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
  }

 private:
  std::filesystem::path path_;
};

inline std::string base64(const std::string& in) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned v = unsigned(uint8_t(in[i])) << 16 | unsigned(uint8_t(in[i + 1])) << 8 |
                       unsigned(uint8_t(in[i + 2]));
    out += {k[v >> 18], k[(v >> 12) & 63], k[(v >> 6) & 63], k[v & 63]};
  }
  if (i + 1 == in.size()) {
    const unsigned v = unsigned(uint8_t(in[i])) << 16;
    out += {k[v >> 18], k[(v >> 12) & 63], '=', '='};
  } else if (i + 2 == in.size()) {
    const unsigned v = unsigned(uint8_t(in[i])) << 16 | unsigned(uint8_t(in[i + 1])) << 8;
    out += {k[v >> 18], k[(v >> 12) & 63], k[(v >> 6) & 63], '='};
  }
  return out;
}

inline std::string read_bytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

template <class T>
std::string bytes_of(const std::vector<T>& v) {
  std::string s(v.size() * sizeof(T), '\0');
  if (!v.empty()) std::memcpy(s.data(), v.data(), s.size());
  return s;
}

// Builds a glTF JSON document whose single buffer is a data URI.
class GltfWriter {
 public:
  nlohmann::json j;
  GltfWriter() { j["asset"] = {{"version", "2.0"}}; }

  // Appends bytes (4-byte aligned) as a new bufferView; returns its index.
  int view(const std::string& bytes, int stride = 0) {
    while (bin_.size() % 4) bin_ += '\0';
    nlohmann::json v = {{"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", bytes.size()}};
    if (stride > 0) v["byteStride"] = stride;
    bin_ += bytes;
    j["bufferViews"].push_back(v);
    return int(j["bufferViews"].size() - 1);
  }
  int accessor(int view, int component_type, size_t count, const std::string& type,
               nlohmann::json extra = nlohmann::json::object()) {
    nlohmann::json a = {{"componentType", component_type}, {"count", count}, {"type", type}};
    if (view >= 0) a["bufferView"] = view;
    a.update(extra);
    j["accessors"].push_back(a);
    return int(j["accessors"].size() - 1);
  }
  int floats(const std::vector<float>& v, const std::string& type) {
    const size_t n = type == "VEC3" ? 3 : type == "VEC2" ? 2 : type == "VEC4" ? 4 : 1;
    return accessor(view(bytes_of(v)), 5126, v.size() / n, type);
  }
  template <class T>
  int indices(const std::vector<T>& v) {
    const int ct = sizeof(T) == 1 ? 5121 : sizeof(T) == 2 ? 5123 : 5125;
    return accessor(view(bytes_of(v)), ct, v.size(), "SCALAR");
  }
  // A mesh with one primitive; returns the mesh index.
  int mesh(nlohmann::json attributes, int indices = -1, int material = -1, int mode = 4,
           const std::string& name = "m") {
    nlohmann::json p = {{"attributes", attributes}, {"mode", mode}};
    if (indices >= 0) p["indices"] = indices;
    if (material >= 0) p["material"] = material;
    j["meshes"].push_back({{"name", name}, {"primitives", {p}}});
    return int(j["meshes"].size() - 1);
  }
  // A node holding mesh `m` in scene 0.
  int node(nlohmann::json n) {
    j["nodes"].push_back(n);
    const int i = int(j["nodes"].size() - 1);
    if (!j.contains("scenes"))
      j["scenes"] = nlohmann::json::array({{{"nodes", nlohmann::json::array()}}});
    j["scenes"][0]["nodes"].push_back(i);
    return i;
  }
  std::string text() {
    nlohmann::json out = j;
    if (!bin_.empty())
      out["buffers"] = {{{"byteLength", bin_.size()},
                         {"uri", "data:application/octet-stream;base64," + base64(bin_)}}};
    return out.dump(1);
  }

 private:
  std::string bin_;
};

// Vertex p of mesh m as a Vec3 (for messages and comparisons).
inline Vec3 pos(const TriangleMesh& m, size_t i) { return Vec3(m.positions[i]); }

inline std::string str(const Vec3& v) { return fmt::format("({}, {}, {})", v.x, v.y, v.z); }

// Unit normal of triangle t from its winding.
inline Vec3 face_normal(const TriangleMesh& m, size_t t) {
  const Vec3 a = pos(m, m.indices[3 * t]), b = pos(m, m.indices[3 * t + 1]),
             c = pos(m, m.indices[3 * t + 2]);
  return normalize(cross(b - a, c - a));
}

inline bool has_warning(const LoadedModel& m, const std::string& needle) {
  for (const auto& w : m.warnings)
    if (w.find(needle) != std::string::npos) return true;
  return false;
}

inline std::string all_warnings(const LoadedModel& m) {
  std::string s;
  for (const auto& w : m.warnings) s += "  " + w + "\n";
  return s;
}

}  // namespace anamorph::test
