// glTF 2.0 (.gltf with external or data-URI buffers, .glb) through tinygltf.
//
// What is read, and how it maps:
//   scene         `scene`, else scene 0 (older files such as Cameras.gltf have no `scene`), else
//                 every root node. Nodes: `matrix` or T * R * S, accumulated down the hierarchy.
//   meshes        each glTF mesh used by any node becomes ONE Prototype (one TriangleMesh per
//                 primitive); every node using it adds an Instance. TRIANGLES are read, strips
//                 and fans converted, points and lines skipped with a warning. A node whose mesh
//                 deforms (a skin, or morph targets whose weights are animated or its own) gets
//                 a prototype of its own and a Deformer (gltf_rig.h) with the rest data; the
//                 static pose is the file's nodes as written, deformed (skinned meshes live in
//                 model space: their instance has the identity transform).
//   animation     nodes, animations and skins into LoadedModel::rig (gltf_rig_reader.h).
//   lights        KHR_lights_punctual, placed by their nodes, in the file's units
//                 (gltf_lights.h converts them).
//   attributes    POSITION, NORMAL, TEXCOORD_n (n from the material's textures) in any
//                 component type, normalized or not, sparse, any byteStride (0 = packed).
//                 Missing normals stay empty: the spec asks for flat shading then.
//   uvs           stored as given: glTF's (0,0) is the image's top-left, as in our textures.
//   materials     MetallicRoughness model: baseColor factor x texture (sRGB), metallic and
//                 roughness factors (which scale the metallicRoughness texture's B and G;
//                 the texture itself is kept unscaled, value white), normal texture + scale,
//                 emissive factor x texture (sRGB) x KHR_materials_emissive_strength, alphaMode
//                 (BLEND: the BSDF's opacity, shadow rays too), doubleSided, KHR_materials_ior,
//                 KHR_materials_specular (factors and textures: the dielectric F0),
//                 KHR_materials_transmission (factor, texture) and _volume (thin or solid,
//                 thickness texture, absorption),
//                 KHR_materials_unlit (the `unlit` kind, the base colour as emission),
//                 KHR_materials_clearcoat and KHR_materials_sheen (factors, textures, the
//                 clear coat's normal texture: the BSDF's layers),
//                 samplers (wrap modes; magFilter NEAREST), KHR_texture_transform.
//   cameras       perspective and orthographic, placed by their node.
// Embedded images are decoded by tinygltf (stb); image files are read with read_image.
#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstring>
#include <deque>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <string_view>
#include <tuple>
#include <variant>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "io/image_io.h"
#include "io/json_nesting.h"

#include "io/read_file.h"
#include "io/read_log.h"
#include "material/metallic_roughness.h"
#include "material/unlit.h"
#include "scene/gltf_animation.h"
#include "scene/gltf_lights.h"
#include "scene/gltf_rig_reader.h"
#include "scene/load_common.h"
#include "scene/load_gltf_accessor.h"
#include "scene/load_mesh_repair.h"
#include "scene/loaders.h"
#include "scene/skinning.h"

namespace anamorph {

namespace fs = std::filesystem;

namespace {

// Extensions whose content this loader maps into our data. Others are warned about.
constexpr std::array<std::string_view, 11> kSupportedExtensions = {
    "KHR_texture_transform",      "KHR_materials_emissive_strength",
    "KHR_mesh_quantization",      "KHR_materials_ior",
    "KHR_lights_punctual",        "KHR_materials_specular",
    "KHR_materials_transmission", "KHR_materials_volume",
    "KHR_materials_unlit",        "KHR_materials_clearcoat",
    "KHR_materials_sheen"};

bool supported(const std::string& ext) {
  return std::find(kSupportedExtensions.begin(), kSupportedExtensions.end(), ext) !=
         kSupportedExtensions.end();
}

// tinygltf image callback: images in data URIs are decoded by tinygltf's own stb loader; image
// files (uri set) are left for read_image, which knows more formats and the colour handling of
// the project, and so are images in buffer views: tinygltf 2.7 hands this callback a buffer
// view's bytes without checking that the view lies inside its buffer (a fuzzed .glb made stb
// read past the end), so they are decoded after loading from the checked view (view_bytes).
bool decode_embedded_image(tinygltf::Image* image, const int index, std::string* err,
                           std::string* warn, int req_width, int req_height,
                           const unsigned char* bytes, int size, void* /*user*/) {
  if (!image->uri.empty() || image->bufferView >= 0) return true;
  return tinygltf::LoadImageData(image, index, err, warn, req_width, req_height, bytes, size,
                                 nullptr);
}

std::string percent_decode(const std::string& s) {
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '%' && i + 2 < s.size() && std::isxdigit(static_cast<unsigned char>(s[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(s[i + 2]))) {
      out += char(std::stoi(s.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += s[i];
    }
  }
  return out;
}

std::string trim(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  return s;
}

double number(const tinygltf::Value& obj, const char* key, double fallback) {
  if (!obj.IsObject() || !obj.Has(key)) return fallback;
  const tinygltf::Value& v = obj.Get(key);
  return v.IsNumber() ? v.GetNumberAsDouble() : fallback;
}

// KHR_materials_specular's factors: a dielectric's F0 = min(F0(ior) x specularColorFactor x
// colour texture, 1) x specularFactor x texture's alpha, F0(ior) = ((ior - 1) / (ior + 1))^2.
void read_specular_factors(const tinygltf::Value& ext, MetallicRoughnessMaterial& mat) {
  mat.specular = std::clamp(number(ext, "specularFactor", 1.0), 0.0, 1.0);
  Color c{1, 1, 1};
  if (ext.IsObject() && ext.Has("specularColorFactor")) {
    const tinygltf::Value& v = ext.Get("specularColorFactor");
    if (v.IsArray() && v.ArrayLen() == 3)
      for (int k = 0; k < 3; ++k)
        if (v.Get(k).IsNumber()) c[k] = std::max(0.0, v.Get(k).GetNumberAsDouble());
  }
  const double r = (mat.ior - 1) / (mat.ior + 1), f0 = std::isfinite(r) ? r * r : 0.04;
  for (int k = 0; k < 3; ++k) mat.specular_color[k] = f0 * c[k];
}

Vec2 vec2(const tinygltf::Value& obj, const char* key, Vec2 fallback) {
  if (!obj.IsObject() || !obj.Has(key)) return fallback;
  const tinygltf::Value& v = obj.Get(key);
  if (!v.IsArray() || v.ArrayLen() != 2 || !v.Get(0).IsNumber() || !v.Get(1).IsNumber())
    return fallback;
  return {v.Get(0).GetNumberAsDouble(), v.Get(1).GetNumberAsDouble()};
}

Wrap wrap_mode(int gl) {
  switch (gl) {
    case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE:
      return Wrap::Clamp;
    case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT:
      return Wrap::Mirror;
    default:
      return Wrap::Repeat;
  }
}

// The node's own transform: `matrix` (column-major) or translation * rotation * scale.
Mat4 local_matrix(const tinygltf::Node& n) {
  Mat4 m = Mat4::identity();
  if (n.matrix.size() == 16) {
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) m.m[r][c] = n.matrix[size_t(c * 4 + r)];
    return m;
  }
  Mat4 t = Mat4::identity(), rot = Mat4::identity(), s = Mat4::identity();
  if (n.translation.size() == 3)
    for (int k = 0; k < 3; ++k) t.m[k][3] = n.translation[size_t(k)];
  if (n.scale.size() == 3)
    for (int k = 0; k < 3; ++k) s.m[k][k] = n.scale[size_t(k)];
  if (n.rotation.size() == 4)  // (normalized there; a zero or non-finite one is no rotation)
    rot = rotation_matrix({n.rotation[0], n.rotation[1], n.rotation[2], n.rotation[3]});
  return t * rot * s;
}

// A textureInfo of any of tinygltf's three kinds.
struct TexRef {
  int index = -1;
  int tex_coord = 0;
  const tinygltf::ExtensionMap* extensions = nullptr;
};
template <class Info>
TexRef tex_ref(const Info& info) {
  return {info.index, info.texCoord, &info.extensions};
}

class GltfBuilder {
 public:
  GltfBuilder(const tinygltf::Model& m, const fs::path& file)
      : m_(m), dir_(file.parent_path()), file_(file.string()) {
    material_index_.assign(m.materials.size(), -1);
    material_uv_set_.assign(m.materials.size(), 0);
    material_textured_.assign(m.materials.size(), false);
    prototype_of_mesh_.assign(m.meshes.size(), kNotBuilt);
  }

  LoadedModel build(const std::string& tinygltf_warnings) {
    for (size_t at = 0; at < tinygltf_warnings.size();) {
      const size_t end = std::min(tinygltf_warnings.find('\n', at), tinygltf_warnings.size());
      if (end > at) warnings_.add(file_ + ": " + tinygltf_warnings.substr(at, end - at));
      at = end + 1;
    }
    check_extensions();
    std::vector<int> roots;
    if (m_.defaultScene >= 0) {
      if (size_t(m_.defaultScene) >= m_.scenes.size())
        throw LoadError(
            fmt::format("scene {} does not exist ({} scenes)", m_.defaultScene, m_.scenes.size()));
      roots = m_.scenes[size_t(m_.defaultScene)].nodes;
    } else if (!m_.scenes.empty()) {
      roots = m_.scenes[0].nodes;
    } else {
      std::vector<bool> is_child(m_.nodes.size(), false);
      for (const auto& n : m_.nodes)
        for (int c : n.children)
          if (c >= 0 && size_t(c) < is_child.size()) is_child[size_t(c)] = true;
      for (size_t i = 0; i < m_.nodes.size(); ++i)
        if (!is_child[i]) roots.push_back(int(i));
    }
    check_tree();
    {
      std::vector<std::string> w;
      rig_ = read_rig(m_, w);
      for (auto& x : w) warnings_.add(file_ + ": " + x);
    }
    for (int r : roots) visit(r, Mat4::identity(), 0);
    finish_rig(rig_);
    rest_pose();
    finish_warnings();
    summarize();
    out_.warnings = warnings_.take();
    out_.rig = std::make_shared<const GltfRig>(std::move(rig_));
    return std::move(out_);
  }

 private:
  static constexpr int kNotBuilt = -1, kEmpty = -2;

  void check_extensions() {
    for (const auto& e : m_.extensionsRequired)
      if (!supported(e))
        warnings_.add(
            fmt::format("{}: required glTF extension {} is not supported; parts of "
                        "the model may be missing or look wrong",
                        file_, e));
    for (const auto& e : m_.extensionsUsed)
      if (!supported(e) && std::find(m_.extensionsRequired.begin(), m_.extensionsRequired.end(),
                                     e) == m_.extensionsRequired.end())
        warnings_.add(
            fmt::format("{}: glTF extension {} is not supported and is ignored", file_, e));
  }

  // glTF nodes form a tree: each node has at most one parent. A node shared by parents would be
  // visited once per path, and a 1 KB file whose 32 levels each list the next node twice names
  // 2^32 instances.
  void check_tree() const {
    std::vector<int> parent(m_.nodes.size(), -1);
    for (size_t p = 0; p < m_.nodes.size(); ++p)
      for (int c : m_.nodes[p].children) {
        if (c < 0 || size_t(c) >= m_.nodes.size())
          throw LoadError(
              fmt::format("node {}: child {} does not exist ({} nodes)", p, c, m_.nodes.size()));
        if (parent[size_t(c)] >= 0)
          throw LoadError(fmt::format(
              "node {} is a child of node {} and of node {}; glTF nodes form a tree (a node "
              "has at most one parent)",
              c, parent[size_t(c)], p));
        parent[size_t(c)] = int(p);
      }
  }

  void visit(int index, const Mat4& parent, size_t depth) {
    if (index < 0 || size_t(index) >= m_.nodes.size())
      throw LoadError(fmt::format("node {} does not exist ({} nodes)", index, m_.nodes.size()));
    if (depth > m_.nodes.size())
      throw LoadError(fmt::format("node hierarchy contains a cycle through node {}", index));
    const tinygltf::Node& n = m_.nodes[size_t(index)];
    const Mat4 world = parent * local_matrix(n);
    const std::string name = n.name.empty() ? fmt::format("node {}", index) : n.name;
    if (n.mesh >= 0) {
      if (size_t(n.mesh) >= m_.meshes.size())
        throw LoadError(fmt::format("node {}: mesh {} does not exist", index, n.mesh));
      if (n.skin >= 0 && size_t(n.skin) >= m_.skins.size())
        throw LoadError(fmt::format("node {}: skin {} does not exist ({} skins)", index, n.skin,
                                    m_.skins.size()));
      const bool skinned = n.skin >= 0;
      const int proto = deforms(index) ? deformed_prototype(index) : prototype(n.mesh);
      if (proto >= 0) {
        bool ok = false;
        const Mat4 placed = skinned ? Mat4::identity() : world;
        const Mat4 inv = inverse(placed, &ok);
        if (ok) {
          out_.instances.push_back({uint32_t(proto), Transform(placed, inv), name, {}});
          rig_.instance_nodes.push_back(index);
          rig_.instance_skinned.push_back(skinned);
        } else {
          ++singular_nodes_;
        }
      }
    }
    if (n.camera >= 0) {
      add_camera(n, name, world);
      rig_.camera_nodes.push_back(index);
    }
    std::vector<std::string> w;
    if (auto l = read_node_light(m_, n, name, world, w)) {
      out_.lights.push_back(std::move(*l));
      rig_.light_nodes.push_back(index);
    }
    for (auto& x : w) warnings_.add(file_ + ": " + x);
    for (int c : n.children) visit(c, world, depth + 1);
  }

  // Whether node `index`'s mesh deforms: a skin, or morph targets with weights of its own or
  // animated.
  bool deforms(int index) const {
    const tinygltf::Node& n = m_.nodes[size_t(index)];
    if (n.skin >= 0) return true;
    const tinygltf::Mesh& gm = m_.meshes[size_t(n.mesh)];
    const bool targets = std::any_of(gm.primitives.begin(), gm.primitives.end(),
                                     [](const auto& p) { return !p.targets.empty(); });
    if (!targets) return false;
    if (!n.weights.empty() && n.weights != gm.weights) return true;
    return morph_animated(index);
  }
  bool morph_animated(int index) const {
    return std::any_of(rig_.channels.begin(), rig_.channels.end(), [&](const AnimChannel& c) {
      return c.node == index && c.path == AnimPath::Weights;
    });
  }

  // A prototype of node `index`'s own for its deforming mesh, with its Deformer; -2 when it
  // has nothing to render.
  int deformed_prototype(int index) {
    const tinygltf::Node& n = m_.nodes[size_t(index)];
    const tinygltf::Mesh& gm = m_.meshes[size_t(n.mesh)];
    Deformer d;
    d.node = index;
    d.skin = n.skin;
    d.morph_animated = morph_animated(index);
    const Skin* skin = n.skin >= 0 ? &rig_.skins[size_t(n.skin)] : nullptr;
    Prototype p;
    p.name = (gm.name.empty() ? fmt::format("mesh {}", n.mesh) : gm.name) +
             fmt::format(" (node {})", index);
    for (size_t i = 0; i < gm.primitives.size(); ++i) {
      std::string name = p.name;
      if (gm.primitives.size() > 1) name += fmt::format(" primitive {}", i);
      Deformer::Part part;
      PartRequest req{&part, &rig_.nodes[size_t(index)].weights, skin};
      if (auto tm = primitive(gm, gm.primitives[i], name, &req)) {
        p.meshes.push_back(std::move(*tm));
        d.parts.push_back(std::move(part));
      }
    }
    if (p.meshes.empty()) return kEmpty;
    out_.prototypes.push_back(std::move(p));
    const auto proto = uint32_t(out_.prototypes.size() - 1);
    d.prototype = proto;
    rig_.deformers.push_back(std::move(d));
    return int(proto);
  }

  // The static pose of deforming meshes: the file's nodes as written.
  void rest_pose() {
    if (rig_.deformers.empty()) return;
    const RigPose pose = pose_rig(rig_, 0, false);
    for (const Deformer& d : rig_.deformers)
      deform(rig_, d, pose, out_.prototypes[d.prototype].meshes);
  }

  void add_camera(const tinygltf::Node& n, const std::string& node_name, const Mat4& world) {
    if (size_t(n.camera) >= m_.cameras.size())
      throw LoadError(fmt::format("node '{}': camera {} does not exist", node_name, n.camera));
    const tinygltf::Camera& c = m_.cameras[size_t(n.camera)];
    ModelCamera mc;
    mc.name = c.name.empty() ? node_name : c.name;
    if (c.type == "perspective") {
      mc.perspective = true;
      mc.yfov = c.perspective.yfov;
      mc.aspect = c.perspective.aspectRatio;
      if (!(mc.yfov > 0 && mc.yfov < kPi))
        throw LoadError(fmt::format("camera '{}': yfov {} is not in (0, pi)", mc.name, mc.yfov));
    } else if (c.type == "orthographic") {
      mc.perspective = false;
      mc.xmag = c.orthographic.xmag;
      mc.ymag = c.orthographic.ymag;
      if (mc.xmag == 0 || mc.ymag == 0)
        throw LoadError(fmt::format("camera '{}': xmag and ymag must not be zero", mc.name));
    } else {
      throw LoadError(
          fmt::format("camera '{}': type '{}' is neither perspective nor "
                      "orthographic",
                      mc.name, c.type));
    }
    mc.world_from_camera = Transform(world);
    out_.cameras.push_back(std::move(mc));
  }

  // Index into out_.prototypes of glTF mesh `mesh`, building it on first use; -2 when it has
  // nothing to render.
  int prototype(int mesh) {
    int& slot = prototype_of_mesh_[size_t(mesh)];
    if (slot != kNotBuilt) return slot;
    const tinygltf::Mesh& gm = m_.meshes[size_t(mesh)];
    Prototype p;
    p.name = gm.name.empty() ? fmt::format("mesh {}", mesh) : gm.name;
    for (size_t i = 0; i < gm.primitives.size(); ++i) {
      std::string name = p.name;
      if (gm.primitives.size() > 1) name += fmt::format(" primitive {}", i);
      if (auto tm = primitive(gm, gm.primitives[i], name)) p.meshes.push_back(std::move(*tm));
    }
    if (p.meshes.empty()) return slot = kEmpty;
    out_.prototypes.push_back(std::move(p));
    return slot = int(out_.prototypes.size() - 1);
  }

  // What a deforming node's primitive also needs: its rest data, its morph weights (instead of
  // the mesh's), its skin.
  struct PartRequest {
    Deformer::Part* part;
    const std::vector<double>* weights;
    const Skin* skin;
  };

  std::optional<TriangleMesh> primitive(const tinygltf::Mesh& gm, const tinygltf::Primitive& pr,
                                        const std::string& name, PartRequest* req = nullptr) {
    const int mode = pr.mode < 0 ? TINYGLTF_MODE_TRIANGLES : pr.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      ++skipped_modes_[mode];
      return std::nullopt;
    }
    auto attr = [&](const std::string& key) {
      auto it = pr.attributes.find(key);
      return it == pr.attributes.end() ? -1 : it->second;
    };
    const int pos = attr("POSITION");
    if (pos < 0) {
      warnings_.add(fmt::format("{}: mesh '{}' has no POSITION; skipped", file_, name));
      return std::nullopt;
    }
    TriangleMesh tm;
    tm.name = name;
    tm.material = pr.material >= 0 ? material(pr.material) : default_material();
    const int uv_set = pr.material >= 0 ? material_uv_set_[size_t(pr.material)] : 0;
    const bool textured = pr.material >= 0 && material_textured_[size_t(pr.material)];

    auto where = [&](const char* what) { return fmt::format("mesh '{}' {}: ", name, what); };
    try {
      read_attributes(pr, pos, uv_set, tm);
    } catch (const LoadError& e) {
      throw LoadError(where("attributes") + e.what());
    }
    if (textured && tm.uvs.empty())
      warnings_.add(
          fmt::format("{}: mesh '{}' has a textured material but no TEXCOORD_{}; its "
                      "textures are read at uv (0, 0)",
                      file_, name, uv_set));
    apply_morph_targets(req ? *req->weights : gm.weights, pr, tm, name);
    if (attr("COLOR_0") >= 0) ++vertex_colors_ignored_;

    std::vector<uint32_t> idx;
    try {
      idx = read_indices(pr, tm.positions.size());
    } catch (const LoadError& e) {
      throw LoadError(where("indices") + e.what());
    }
    tm.indices = to_triangles(idx, mode);
    check_mesh(tm, repairs_);
    if (tm.indices.empty()) return std::nullopt;
    if (req) {
      std::vector<std::string> w;
      try {
        *req->part = read_deformer_part(m_, pr, tm.normals, req->skin, w);
      } catch (const LoadError& e) {
        throw LoadError(where("deformation") + e.what());
      }
      for (auto& x : w) warnings_.add(file_ + ": " + x);
    }
    return tm;
  }

  // Positions (accessor `pos`), normals and the material's TEXCOORD set.
  void read_attributes(const tinygltf::Primitive& pr, int pos, int uv_set, TriangleMesh& tm) {
    const auto attr = [&](const std::string& key) {
      auto it = pr.attributes.find(key);
      return it == pr.attributes.end() ? -1 : it->second;
    };
    tm.positions = to_vec3(read_accessor_floats(m_, pos, 3));
    if (const int a = attr("NORMAL"); a >= 0) tm.normals = to_vec3(read_accessor_floats(m_, a, 3));
    if (const int a = attr(fmt::format("TEXCOORD_{}", uv_set)); a >= 0) {
      const auto f = read_accessor_floats(m_, a, 2);
      tm.uvs.resize(f.size() / 2);
      for (size_t i = 0; i < tm.uvs.size(); ++i) tm.uvs[i] = {f[2 * i], f[2 * i + 1]};
    }
  }

  // The primitive's indices, or 0..n-1 without an accessor.
  std::vector<uint32_t> read_indices(const tinygltf::Primitive& pr, size_t n) {
    if (pr.indices >= 0) return read_accessor_indices(m_, pr.indices);
    std::vector<uint32_t> idx(n);
    std::iota(idx.begin(), idx.end(), 0u);
    return idx;
  }

  static std::vector<Vec3f> to_vec3(const std::vector<float>& f) {
    std::vector<Vec3f> v(f.size() / 3);
    for (size_t i = 0; i < v.size(); ++i) v[i] = {f[3 * i], f[3 * i + 1], f[3 * i + 2]};
    return v;
  }

  // Triangle list from TRIANGLES, TRIANGLE_STRIP or TRIANGLE_FAN (glTF spec, section 3.7.2.1).
  static std::vector<uint32_t> to_triangles(const std::vector<uint32_t>& idx, int mode) {
    if (mode == TINYGLTF_MODE_TRIANGLES) return idx;
    std::vector<uint32_t> out;
    for (size_t i = 0; i + 2 < idx.size(); ++i) {
      if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        // Every other triangle swaps its first two vertices to keep the winding.
        const size_t odd = i % 2;
        out.insert(out.end(), {idx[i + odd], idx[i + 1 - odd], idx[i + 2]});
      } else {
        out.insert(out.end(), {idx[i + 1], idx[i + 2], idx[0]});
      }
    }
    return out;
  }

  // Static pose: base + sum of weight * target for the given weights.
  void apply_morph_targets(const std::vector<double>& weights, const tinygltf::Primitive& pr,
                           TriangleMesh& tm, const std::string& name) {
    for (size_t t = 0; t < pr.targets.size() && t < weights.size(); ++t) {
      const double w = weights[t];
      if (w == 0) continue;
      auto add = [&](const char* key, std::vector<Vec3f>& dst) {
        auto it = pr.targets[t].find(key);
        if (it == pr.targets[t].end() || dst.empty()) return;
        const auto d = to_vec3(read_accessor_floats(m_, it->second, 3));
        if (d.size() != dst.size())
          throw LoadError(fmt::format("mesh '{}': morph target {} {} has {} elements, base has {}",
                                      name, t, key, d.size(), dst.size()));
        for (size_t i = 0; i < dst.size(); ++i) dst[i] += d[i] * float(w);
      };
      add("POSITION", tm.positions);
      add("NORMAL", tm.normals);
    }
  }

  uint32_t default_material() {
    if (default_material_ < 0) {
      // glTF's default: white, metallic 1, roughness 1, single-sided.
      auto mat = std::make_unique<MetallicRoughnessMaterial>();
      mat->name = "glTF default";
      mat->base_color = Texture::constant({1, 1, 1});
      mat->double_sided = false;
      out_.materials.push_back(std::move(mat));
      default_material_ = int(out_.materials.size() - 1);
    }
    return uint32_t(default_material_);
  }

  uint32_t material(int index) {
    if (size_t(index) >= m_.materials.size())
      throw LoadError(
          fmt::format("material {} does not exist ({} materials)", index, m_.materials.size()));
    int& slot = material_index_[size_t(index)];
    if (slot < 0) {
      out_.materials.push_back(convert_material(index));
      slot = int(out_.materials.size() - 1);
    }
    return uint32_t(slot);
  }

  std::unique_ptr<Material> convert_material(int index) {
    const tinygltf::Material& gm = m_.materials[size_t(index)];
    auto owned = std::make_unique<MetallicRoughnessMaterial>();
    MetallicRoughnessMaterial& mat = *owned;
    mat.name = gm.name.empty() ? fmt::format("material {}", index) : gm.name;
    if (gm.alphaMode == "MASK") {
      mat.alpha_mode = Material::AlphaMode::Mask;
      mat.alpha_cutoff = gm.alphaCutoff;
    } else if (gm.alphaMode == "BLEND") {
      mat.alpha_mode = Material::AlphaMode::Blend;  // transparency: the BSDF's opacity
    }
    mat.double_sided = gm.doubleSided;

    int uv_set = -1;
    auto texture = [&](const TexRef& ref, bool srgb, Color value, float alpha_scale) {
      int set = 0;
      Texture t = make_texture(ref, srgb, value, alpha_scale, &set);
      if (t.kind == Texture::Kind::Image) {
        if (uv_set < 0) uv_set = set;
        if (set != uv_set)
          warnings_.add(
              fmt::format("{}: material '{}' uses several TEXCOORD sets; all its "
                          "textures use TEXCOORD_{}",
                          file_, mat.name, uv_set));
      }
      return t;
    };

    read_base_color(gm, mat, texture);
    const auto& pbr = gm.pbrMetallicRoughness;
    mat.metallic = pbr.metallicFactor;
    mat.roughness = pbr.roughnessFactor;
    if (pbr.metallicRoughnessTexture.index >= 0)
      mat.metallic_roughness = texture(tex_ref(pbr.metallicRoughnessTexture), false, {1, 1, 1}, 1);
    if (gm.normalTexture.index >= 0) {
      mat.normal_map = texture(tex_ref(gm.normalTexture), false, {1, 1, 1}, 1);
      mat.has_normal_map = mat.normal_map.kind == Texture::Kind::Image;
      mat.normal_scale = gm.normalTexture.scale;
    }

    read_emission(gm, mat, texture);
    if (auto it = gm.extensions.find("KHR_materials_ior"); it != gm.extensions.end())
      mat.ior = number(it->second, "ior", 1.5);
    read_specular(gm, mat, texture);
    read_transmission(gm, mat, texture);
    read_layers(gm, mat, texture);
    material_uv_set_[size_t(index)] = std::max(uv_set, 0);
    material_textured_[size_t(index)] = uv_set >= 0;
    if (gm.extensions.count("KHR_materials_unlit")) return unlit(mat);
    return owned;
  }

  // pbrMetallicRoughness's base colour: factor times texture. The factor's alpha multiplies the
  // texture's alpha when the material uses alpha; Texture has no alpha factor, so it is baked
  // into the image (or a 1x1 image when there is no texture).
  template <class TextureFn>
  void read_base_color(const tinygltf::Material& gm, MetallicRoughnessMaterial& mat,
                       TextureFn&& texture) {
    const auto& pbr = gm.pbrMetallicRoughness;
    Color base{1, 1, 1};
    double alpha = 1;
    if (pbr.baseColorFactor.size() == 4) {
      base = {pbr.baseColorFactor[0], pbr.baseColorFactor[1], pbr.baseColorFactor[2]};
      alpha = pbr.baseColorFactor[3];
    }
    const bool uses_alpha = mat.alpha_mode != Material::AlphaMode::Opaque;
    const float alpha_scale = uses_alpha ? float(alpha) : 1.0f;
    if (pbr.baseColorTexture.index >= 0)
      mat.base_color = texture(tex_ref(pbr.baseColorTexture), true, base, alpha_scale);
    else if (alpha_scale < 1)
      mat.base_color = constant_with_alpha(base, alpha_scale);
    else
      mat.base_color = Texture::constant(base);
  }

  // The emissive factor times its texture, and KHR_materials_emissive_strength.
  template <class TextureFn>
  void read_emission(const tinygltf::Material& gm, MetallicRoughnessMaterial& mat,
                     TextureFn&& texture) {
    Color emissive{0, 0, 0};
    if (gm.emissiveFactor.size() == 3)
      emissive = {gm.emissiveFactor[0], gm.emissiveFactor[1], gm.emissiveFactor[2]};
    if (auto it = gm.extensions.find("KHR_materials_emissive_strength"); it != gm.extensions.end())
      mat.emission_strength = number(it->second, "emissiveStrength", 1.0);
    if (max_component(emissive) > 0) {
      mat.emission = gm.emissiveTexture.index >= 0
                         ? texture(tex_ref(gm.emissiveTexture), true, emissive, 1)
                         : Texture::constant(emissive);
    }
  }

  // KHR_materials_specular: its factors and textures (specularTexture's alpha, linear;
  // specularColorTexture, sRGB).
  template <class TextureFn>
  void read_specular(const tinygltf::Material& gm, MetallicRoughnessMaterial& mat,
                     TextureFn&& texture) {
    const auto it = gm.extensions.find("KHR_materials_specular");
    if (it == gm.extensions.end()) return;
    read_specular_factors(it->second, mat);
    if (const auto r = ext_tex_ref(it->second, "specularTexture"))
      mat.specular_texture = texture(*r, false, {1, 1, 1}, 1);
    if (const auto r = ext_tex_ref(it->second, "specularColorTexture"))
      mat.specular_color_texture = texture(*r, true, {1, 1, 1}, 1);
  }

  // KHR_materials_transmission's factor and texture (R) and KHR_materials_volume: with a
  // thickness a refracting solid absorbing sigma = -ln(attenuationColor) / attenuationDistance
  // per channel (thin where the thickness texture's G is 0), without one a thin wall.
  template <class TextureFn>
  void read_transmission(const tinygltf::Material& gm, MetallicRoughnessMaterial& mat,
                         TextureFn&& texture) {
    const auto t = gm.extensions.find("KHR_materials_transmission");
    if (t == gm.extensions.end()) return;
    mat.transmission = std::clamp(number(t->second, "transmissionFactor", 0.0), 0.0, 1.0);
    if (!(mat.transmission > 0)) mat.transmission = 0;
    if (const auto r = ext_tex_ref(t->second, "transmissionTexture"))
      mat.transmission_texture = texture(*r, false, {1, 1, 1}, 1);
    const auto v = gm.extensions.find("KHR_materials_volume");
    mat.thin = v == gm.extensions.end() || !(number(v->second, "thicknessFactor", 0.0) > 0);
    if (mat.thin) return;
    if (const auto r = ext_tex_ref(v->second, "thicknessTexture"))
      mat.thickness_texture = texture(*r, false, {1, 1, 1}, 1);
    const double distance = number(v->second, "attenuationDistance", kInf);
    Color c{1, 1, 1};
    if (v->second.Has("attenuationColor")) {
      const tinygltf::Value& a = v->second.Get("attenuationColor");
      if (a.IsArray() && a.ArrayLen() == 3)
        for (int k = 0; k < 3; ++k)
          if (a.Get(k).IsNumber()) c[k] = std::clamp(a.Get(k).GetNumberAsDouble(), 0.0, 1.0);
    }
    if (!(distance > 0)) return;
    // (A colour of 0 absorbs everything: a large finite coefficient, within the key's range.)
    for (int k = 0; k < 3; ++k) mat.absorption[k] = std::min(-std::log(c[k]) / distance, 1e30);
  }

  // KHR_materials_clearcoat and KHR_materials_sheen: factors and textures (their textureInfo
  // objects are extension JSON, read by ext_tex_ref).
  template <class TextureFn>
  void read_layers(const tinygltf::Material& gm, MetallicRoughnessMaterial& mat,
                   TextureFn&& texture) {
    const Color white{1, 1, 1};
    if (const auto c = gm.extensions.find("KHR_materials_clearcoat"); c != gm.extensions.end()) {
      const tinygltf::Value& x = c->second;
      mat.clearcoat = std::clamp(number(x, "clearcoatFactor", 0.0), 0.0, 1.0);
      if (!(mat.clearcoat > 0)) mat.clearcoat = 0;
      mat.clearcoat_roughness = std::clamp(number(x, "clearcoatRoughnessFactor", 0.0), 0.0, 1.0);
      if (!(mat.clearcoat_roughness >= 0)) mat.clearcoat_roughness = 0;
      if (const auto r = ext_tex_ref(x, "clearcoatTexture"))
        mat.clearcoat_texture = texture(*r, false, white, 1);
      if (const auto r = ext_tex_ref(x, "clearcoatRoughnessTexture"))
        mat.clearcoat_roughness_texture = texture(*r, false, white, 1);
      if (const auto r = ext_tex_ref(x, "clearcoatNormalTexture")) {
        mat.clearcoat_normal = texture(*r, false, white, 1);
        mat.has_clearcoat_normal = mat.clearcoat_normal.kind == Texture::Kind::Image;
        const double scale = number(x.Get("clearcoatNormalTexture"), "scale", 1.0);
        mat.clearcoat_normal_scale = std::isfinite(scale) ? scale : 1.0;
      }
    }
    if (const auto h = gm.extensions.find("KHR_materials_sheen"); h != gm.extensions.end()) {
      const tinygltf::Value& x = h->second;
      mat.sheen_color = color3(x, "sheenColorFactor");
      mat.sheen_roughness = std::clamp(number(x, "sheenRoughnessFactor", 0.0), 0.0, 1.0);
      if (!(mat.sheen_roughness >= 0)) mat.sheen_roughness = 0;
      if (const auto r = ext_tex_ref(x, "sheenColorTexture"))
        mat.sheen_color_texture = texture(*r, true, white, 1);
      if (const auto r = ext_tex_ref(x, "sheenRoughnessTexture"))
        mat.sheen_roughness_texture = texture(*r, false, white, 1);
    }
  }

  // A colour factor of an extension: 3 numbers, each clamped to 0..1 (NaN: 0); default black.
  static Color color3(const tinygltf::Value& obj, const char* key) {
    Color c{0, 0, 0};
    if (!obj.IsObject() || !obj.Has(key)) return c;
    const tinygltf::Value& v = obj.Get(key);
    if (!v.IsArray() || v.ArrayLen() != 3) return c;
    for (int k = 0; k < 3; ++k)
      if (v.Get(k).IsNumber()) {
        const double x = v.Get(k).GetNumberAsDouble();
        c[k] = x > 0 ? std::min(x, 1.0) : 0.0;
      }
    return c;
  }

  // A textureInfo inside an extension's JSON: its index, texCoord and own extensions (kept
  // alive in ext_maps_ for TexRef's pointer). None when absent or without a valid index.
  std::optional<TexRef> ext_tex_ref(const tinygltf::Value& obj, const char* key) {
    if (!obj.IsObject() || !obj.Has(key)) return std::nullopt;
    const tinygltf::Value& info = obj.Get(key);
    const double index = number(info, "index", -1);
    if (!(index >= 0) || index > double(std::numeric_limits<int>::max())) return std::nullopt;
    const double set = number(info, "texCoord", 0);
    TexRef ref{int(index), set >= 0 && set <= 255 ? int(set) : 0, nullptr};
    if (info.Has("extensions") && info.Get("extensions").IsObject()) {
      const tinygltf::Value& e = info.Get("extensions");
      tinygltf::ExtensionMap map;
      for (const std::string& k : e.Keys()) map.emplace(k, e.Get(k));
      ext_maps_.push_back(std::move(map));
      ref.extensions = &ext_maps_.back();
    }
    return ref;
  }

  // KHR_materials_unlit: the base colour (factor x texture) shown as emission.
  static std::unique_ptr<Material> unlit(const MetallicRoughnessMaterial& mat) {
    auto u = std::make_unique<UnlitMaterial>();
    static_cast<Material&>(*u) = static_cast<const Material&>(mat);
    u->emission = mat.base_color;
    u->emission_strength = 1;
    return u;
  }

  static Texture constant_with_alpha(Color c, float alpha) {
    Image img;
    img.width = img.height = 1;
    img.channels = 4;
    img.pixels = {1, 1, 1, alpha};
    Texture t;
    t.kind = Texture::Kind::Image;
    t.value = c;
    t.image = std::make_shared<const MipMap>(std::move(img));
    return t;
  }

  Texture make_texture(const TexRef& ref, bool srgb, Color value, float alpha_scale, int* uv_set) {
    if (ref.index < 0 || size_t(ref.index) >= m_.textures.size())
      throw LoadError(
          fmt::format("texture {} does not exist ({} textures)", ref.index, m_.textures.size()));
    const tinygltf::Texture& gt = m_.textures[size_t(ref.index)];
    if (gt.source < 0) {
      warnings_.add(
          fmt::format("{}: texture {} has no image we can read (only an extension's "
                      "source); its factor is used alone",
                      file_, ref.index));
      return Texture::constant(value);
    }
    Texture t;
    t.kind = Texture::Kind::Image;
    t.value = value;
    t.image = image(gt.source, srgb, alpha_scale);
    if (!t.image) return Texture::constant(value);  // unreadable image file, warned
    if (gt.sampler >= 0) {
      if (size_t(gt.sampler) >= m_.samplers.size())
        throw LoadError(
            fmt::format("texture {}: sampler {} does not exist", ref.index, gt.sampler));
      const tinygltf::Sampler& s = m_.samplers[size_t(gt.sampler)];
      t.wrap_s = wrap_mode(s.wrapS);
      t.wrap_t = wrap_mode(s.wrapT);
      t.nearest = s.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
    }
    *uv_set = ref.tex_coord;
    if (ref.extensions) {
      auto it = ref.extensions->find("KHR_texture_transform");
      if (it != ref.extensions->end()) {
        const tinygltf::Value& x = it->second;
        t.uv_transform = UvTransform::from_offset_rotation_scale(
            vec2(x, "offset", {0, 0}), number(x, "rotation", 0), vec2(x, "scale", {1, 1}));
        *uv_set = int(number(x, "texCoord", ref.tex_coord));
      }
    }
    return t;
  }

  std::shared_ptr<const MipMap> image(int source, bool srgb, float alpha_scale) {
    if (size_t(source) >= m_.images.size())
      throw LoadError(fmt::format("image {} does not exist ({} images)", source, m_.images.size()));
    const auto key = std::make_tuple(source, srgb, alpha_scale);
    if (auto it = images_.find(key); it != images_.end()) return it->second;
    const tinygltf::Image& gi = m_.images[size_t(source)];
    Image img;
    if (!gi.uri.empty()) {
      // A missing or unreadable image file is a warning, not an error: the material's
      // factor still renders, and models often travel without some of their textures.
      const fs::path path = dir_ / percent_decode(gi.uri);
      const ReadRole role("an image that " + file_ + " uses");
      try {
        img = read_image(path, srgb);
      } catch (const std::exception& e) {
        warnings_.add(
            fmt::format("{}: image {} ({}) cannot be read ({}); its texture's factor "
                        "is used alone",
                        file_, source, path.string(), e.what()));
        images_.emplace(key, nullptr);
        return nullptr;
      }
    } else if (gi.bufferView >= 0) {
      size_t size = 0;
      const unsigned char* bytes =
          buffer_view_bytes(m_, gi.bufferView, &size, fmt::format("image {}", source));
      try {
        img = decode_image(std::vector<unsigned char>(bytes, bytes + size), srgb,
                           fmt::format("{} image {}", file_, source));
      } catch (const std::exception& e) {
        throw LoadError(e.what());
      }
    } else {
      img = decoded_image(gi, source, srgb);
    }
    if (alpha_scale != 1 && img.channels == 4)
      for (size_t i = 3; i < img.pixels.size(); i += 4) img.pixels[i] *= alpha_scale;
    auto mip = std::make_shared<const MipMap>(std::move(img));
    images_.emplace(key, mip);
    return mip;
  }

  // tinygltf's decoded 8- or 16-bit image as linear float RGBA.
  static Image decoded_image(const tinygltf::Image& gi, int source, bool srgb) {
    const int comp = gi.component, bytes = gi.bits == 16 ? 2 : 1;
    if (gi.width <= 0 || gi.height <= 0 || comp < 1 || comp > 4 ||
        gi.image.size() < size_t(gi.width) * size_t(gi.height) * size_t(comp * bytes))
      throw LoadError(fmt::format("image {}: not decoded ({}x{}, {} channels, {} bytes)", source,
                                  gi.width, gi.height, comp, gi.image.size()));
    Image img;
    img.width = gi.width;
    img.height = gi.height;
    img.channels = 4;
    img.pixels.resize(size_t(img.width) * size_t(img.height) * 4);
    const double scale = bytes == 2 ? 1.0 / 65535.0 : 1.0 / 255.0;
    const size_t n = size_t(img.width) * size_t(img.height);
    for (size_t i = 0; i < n; ++i) {
      float v[4];
      for (int c = 0; c < comp; ++c) {
        const size_t at = (i * size_t(comp) + size_t(c)) * size_t(bytes);
        const unsigned raw = bytes == 2 ? unsigned(gi.image[at]) | unsigned(gi.image[at + 1]) << 8
                                        : unsigned(gi.image[at]);
        v[c] = float(raw * scale);
      }
      // Grey (+alpha) images spread to RGB (+A).
      float rgba[4] = {v[0], comp >= 3 ? v[1] : v[0], comp >= 3 ? v[2] : v[0],
                       comp == 4 ? v[3] : (comp == 2 ? v[1] : 1.0f)};
      for (int c = 0; c < 3; ++c)
        img.pixels[4 * i + size_t(c)] = srgb ? srgb_to_linear(rgba[c]) : rgba[c];
      img.pixels[4 * i + 3] = rgba[3];
    }
    return img;
  }

  // What the file holds and what of it was read, for `anamorph info`.
  void summarize() {
    std::vector<std::string>& o = out_.summary;
    size_t channels = 0, targets = 0;
    for (const auto& a : m_.animations) channels += a.channels.size();
    for (const auto& mesh : m_.meshes)
      for (const auto& p : mesh.primitives) targets += p.targets.size();
    o.push_back(fmt::format("{}: glTF {}{}", file_, m_.asset.version,
                            m_.asset.generator.empty() ? "" : " by " + m_.asset.generator));
    o.push_back(fmt::format(
        "  {} scene(s), {} node(s), {} mesh(es), {} material(s), {} texture(s), {} image(s)",
        m_.scenes.size(), m_.nodes.size(), m_.meshes.size(), m_.materials.size(),
        m_.textures.size(), m_.images.size()));
    o.push_back(fmt::format(
        "  {} camera(s), {} light(s), {} animation(s) ({} channel(s)), {} skin(s), {} morph "
        "target(s)",
        m_.cameras.size(), m_.lights.size(), m_.animations.size(), channels, m_.skins.size(),
        targets));
    for (const auto& e : m_.extensionsUsed) {
      const bool required = std::find(m_.extensionsRequired.begin(), m_.extensionsRequired.end(),
                                      e) != m_.extensionsRequired.end();
      o.push_back(fmt::format("  extension {}{}: {}", e, required ? " (required)" : "",
                              supported(e) ? "read" : "not read (ignored)"));
    }
  }

  void finish_warnings() {
    add_repair_warnings(repairs_, file_, buffer_);
    for (auto& w : buffer_) warnings_.add(std::move(w));
    for (const auto& [mode, count] : skipped_modes_)
      warnings_.add(fmt::format("{}: {} primitive(s) of mode {} (points or lines) skipped", file_,
                                count, mode));
    if (singular_nodes_ > 0)
      warnings_.add(
          fmt::format("{}: {} mesh node(s) with a singular (zero-scale) transform "
                      "skipped",
                      file_, singular_nodes_));
    if (vertex_colors_ignored_ > 0)
      warnings_.add(fmt::format("{}: COLOR_0 vertex colours ignored on {} primitive(s)", file_,
                                vertex_colors_ignored_));
  }

  const tinygltf::Model& m_;
  fs::path dir_;
  std::string file_;
  LoadedModel out_;
  WarningList warnings_;
  std::vector<std::string> buffer_;
  MeshRepairs repairs_;
  std::vector<int> material_index_, material_uv_set_, prototype_of_mesh_;
  std::vector<bool> material_textured_;
  int default_material_ = -1;
  std::map<std::tuple<int, bool, float>, std::shared_ptr<const MipMap>> images_;
  std::map<int, size_t> skipped_modes_;
  std::deque<tinygltf::ExtensionMap> ext_maps_;  // extension textureInfos' own extensions
  size_t singular_nodes_ = 0;
  GltfRig rig_;
  size_t vertex_colors_ignored_ = 0;
};

// The JSON of a .gltf, or of a .glb's first chunk (its header: magic, version, length, then the
// chunk's length and type), as far as the file holds it.
std::string_view gltf_json(const std::vector<unsigned char>& bytes, bool binary) {
  const auto* text = reinterpret_cast<const char*>(bytes.data());
  if (!binary) return {text, bytes.size()};
  if (bytes.size() < 20) return {};
  uint32_t length = 0;
  std::memcpy(&length, bytes.data() + 12, 4);
  return {text + 20, std::min<size_t>(length, bytes.size() - 20)};
}

// tinygltf reads a model's external buffers through these: io/read_file.h's reader (a FIFO, a
// device or a directory refused at once, the size bounded, the editor's confinement applied)
// instead of tinygltf's std::ifstream, and no shell-style expansion of the name (tinygltf's
// default runs wordexp(3) on it).
// (a file that is there but cannot be read "exists": reading it then says why)
bool gltf_file_exists(const std::string& file, void*) {
  const auto opened = open_input(file, kModelInput);
  const auto* failure = std::get_if<ReadFailure>(&opened);
  return !failure || failure->error != ENOENT;
}
std::string gltf_expand_path(const std::string& file, void*) { return file; }
bool gltf_read_file(std::vector<unsigned char>* out, std::string* err, const std::string& file,
                    void*) {
  if (const auto failure = read_whole_file(file, out, kModelInput)) {
    if (err) *err += describe(*failure, file) + "\n";
    return false;
  }
  return true;
}
bool gltf_no_writes(std::string* err, const std::string&, const std::vector<unsigned char>&,
                    void*) {
  if (err) *err += "the glTF loader writes no files\n";
  return false;
}
const tinygltf::FsCallbacks kGltfFiles{&gltf_file_exists, &gltf_expand_path, &gltf_read_file,
                                       &gltf_no_writes, nullptr};

}  // namespace

LoadedModel load_gltf(const fs::path& file) {
  const std::vector<unsigned char> bytes = read_file_bytes(file, kModelInput);
  if (bytes.size() > std::numeric_limits<unsigned>::max())
    throw LoadError(file.string() + ": file too large for the glTF parser");
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&decode_embedded_image, nullptr);
  loader.SetFsCallbacks(kGltfFiles);
  tinygltf::Model model;
  std::string err, warn;
  const std::string base_dir = file.parent_path().string();
  // The container is recognised by its magic, not its extension: a .gltf that is really a .glb
  // still loads.
  const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  if (const std::string e = json_nesting_error(gltf_json(bytes, binary)); !e.empty())
    throw LoadError(file.string() + ": its JSON is " + e);
  bool ok = false;
  try {
    // (Files tinygltf opens itself are logged below with their roles, not as it reads them.)
    const ReadLogScope unlogged(nullptr);
    ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(),
                                              unsigned(bytes.size()), base_dir)
                : loader.LoadASCIIFromString(&model, &err, &warn,
                                             reinterpret_cast<const char*>(bytes.data()),
                                             unsigned(bytes.size()), base_dir);
  } catch (const std::exception& e) {
    ok = false;
    err = e.what();
  }
  if (!ok)
    throw LoadError(file.string() + ": " + (err.empty() ? "not a valid glTF file" : trim(err)));
  {
    // tinygltf read the external buffers itself.
    const ReadRole role("a buffer of " + file.string());
    for (const tinygltf::Buffer& b : model.buffers)
      if (!b.uri.empty() && b.uri.rfind("data:", 0) != 0)
        note_read(file.parent_path() / percent_decode(b.uri));
  }
  if (model.asset.version.empty() || model.asset.version[0] != '2')
    throw LoadError(file.string() + ": glTF version '" + model.asset.version +
                    "' is not supported (2.x only)");
  try {
    return GltfBuilder(model, file).build(warn);
  } catch (const LoadError& e) {
    throw LoadError(file.string() + ": " + e.what());
  }
}

}  // namespace anamorph
