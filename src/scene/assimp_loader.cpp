// Every format assimp reads (OBJ/MTL, PLY, STL, ...) into the Whitted material model.
//
// Post-processing, chosen deliberately:
//   Triangulate             quads and polygons (OBJ, PLY) become triangles.
//   JoinIdenticalVertices   indexed meshes instead of one vertex per corner.
//   SortByPType             points and lines land in meshes of their own, which are skipped.
//   ValidateDataStructure   assimp's own consistency check; failures become LoadErrors.
// Not used: GenNormals/GenSmoothNormals (a mesh without normals gets smooth normals from
// generate_normals with a 60 degree crease, so cubes keep hard edges even where the file shares
// their corner vertices), FlipUVs (the v flip below is explicit), PreTransformVertices (the node
// hierarchy becomes instances), GlobalScale and MakeLeftHanded (they change units or axes),
// FindDegenerates/FindInvalidData (check_mesh does that and reports counts).
//
// UVs: assimp uses the OpenGL convention, v = 0 at the image's bottom row; our textures have
// (0,0) at the top-left like glTF, so v is stored as 1 - v.
//
// Materials (MTL names in brackets):
//   base_color = diffuse [Kd], times the diffuse texture [map_Kd] when there is one (the MTL
//   rule: the map is multiplied by Kd); specular [Ks]; exponent [Ns] when > 0; emission [Ke],
//   times the emissive texture [map_Ke]; ior [Ni] when not 1 (assimp reports 1 when absent);
//   transmission = 1 - opacity [d] when d < 1; reflectivity = max(Ks) for the ray-traced
//   illumination models [illum 3..7]; tangent-space normal map [norm].
//   OBJ only: a material with no emission [Ke] whose ambient colour [Ka] exceeds 1 in any
//   component is emissive with radiance Ka. Ka > 1 cannot be a reflectance, and files such as
//   the classic Cornell box (`Ka 20 20 20` for the light) use it to mean emission; a warning
//   names each material read this way.
//   Formats without materials (PLY, STL) get our default grey instead of assimp's white with a
//   full specular highlight.
//
// Instancing: an assimp mesh referenced by one node is baked into the file's main prototype
// with that node's transform; a mesh referenced by several nodes is built once as a prototype of
// its own and placed by one instance per reference.
#include <algorithm>
#include <cstring>
#include <map>
#include <optional>

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include <fmt/format.h>

#include "io/confined_folder.h"
#include "io/read_file.h"
#include "io/read_log.h"
#include "material/whitted.h"
#include "scene/assimp_child.h"
#include "scene/isolated.h"
#include "scene/load_common.h"
#include "scene/load_mesh_repair.h"
#include "scene/load_validate.h"
#include "scene/loaders.h"

namespace anamorph {

namespace fs = std::filesystem;

namespace {

constexpr double kCreaseDegrees = 60;

Mat4 to_mat4(const aiMatrix4x4& a) {
  Mat4 m;
  const float* p = &a.a1;  // row-major, a1..a4 is the first row
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m.m[r][c] = p[r * 4 + c];
  return m;
}

Color to_color(const aiColor3D& c) { return {c.r, c.g, c.b}; }

Wrap to_wrap(aiTextureMapMode m) {
  switch (m) {
    case aiTextureMapMode_Clamp:
    case aiTextureMapMode_Decal:
      return Wrap::Clamp;
    case aiTextureMapMode_Mirror:
      return Wrap::Mirror;
    default:
      return Wrap::Repeat;
  }
}

class AssimpBuilder {
 public:
  AssimpBuilder(const aiScene& s, const fs::path& file, std::vector<std::string> mesh_names)
      : s_(s),
        mesh_names_(std::move(mesh_names)),
        dir_(file.parent_path()),
        file_(file.string()),
        is_obj_(lowercase_extension(file) == ".obj"),
        stem_(file.stem().string()) {
    material_index_.assign(s.mNumMaterials, -1);
  }

  LoadedModel build() {
    // Which node references each mesh, with the node's world transform.
    std::vector<std::vector<std::pair<Mat4, std::string>>> refs(s_.mNumMeshes);
    if (s_.mRootNode) collect(*s_.mRootNode, Mat4::identity(), refs, 0);

    std::vector<std::optional<TriangleMesh>> meshes(s_.mNumMeshes);
    for (unsigned i = 0; i < s_.mNumMeshes; ++i)
      if (!refs[i].empty()) meshes[i] = convert_mesh(i);

    Prototype main;
    main.name = stem_;
    for (unsigned i = 0; i < s_.mNumMeshes; ++i) {
      if (!meshes[i] || refs[i].empty()) continue;
      if (refs[i].size() == 1) {
        TriangleMesh tm = *meshes[i];
        bake(tm, refs[i][0].first);
        main.meshes.push_back(std::move(tm));
        continue;
      }
      Prototype shared;
      shared.name = meshes[i]->name;
      shared.meshes.push_back(std::move(*meshes[i]));
      out_.prototypes.push_back(std::move(shared));
      const auto proto = uint32_t(out_.prototypes.size() - 1);
      for (const auto& [m, node] : refs[i]) add_instance(proto, m, node);
    }
    if (!main.meshes.empty()) {
      out_.prototypes.push_back(std::move(main));
      out_.instances.push_back({uint32_t(out_.prototypes.size() - 1), Transform(), stem_, {}});
    }

    std::vector<std::string> repair;
    add_repair_warnings(repairs_, file_, repair);
    for (auto& w : repair) warnings_.add(std::move(w));
    if (skipped_meshes_ > 0)
      warnings_.add(fmt::format("{}: {} point/line mesh(es) skipped", file_, skipped_meshes_));
    if (singular_ > 0)
      warnings_.add(
          fmt::format("{}: {} instance(s) with a singular transform skipped", file_, singular_));
    if (s_.mNumCameras > 0 || s_.mNumLights > 0)
      warnings_.add(fmt::format("{}: {} camera(s) and {} light(s) in the file are ignored", file_,
                                s_.mNumCameras, s_.mNumLights));
    out_.warnings = warnings_.take();
    return std::move(out_);
  }

 private:
  void collect(const aiNode& n, const Mat4& parent,
               std::vector<std::vector<std::pair<Mat4, std::string>>>& refs, int depth) {
    if (depth > 1000) throw LoadError("node hierarchy deeper than 1000 levels");
    const Mat4 world = parent * to_mat4(n.mTransformation);
    for (unsigned k = 0; k < n.mNumMeshes; ++k) {
      const unsigned mi = n.mMeshes[k];
      if (mi >= s_.mNumMeshes)
        throw LoadError(
            fmt::format("node '{}' names mesh {} of {}", n.mName.C_Str(), mi, s_.mNumMeshes));
      refs[mi].emplace_back(world, n.mName.C_Str());
    }
    for (unsigned c = 0; c < n.mNumChildren; ++c)
      if (n.mChildren[c]) collect(*n.mChildren[c], world, refs, depth + 1);
  }

  void add_instance(uint32_t proto, const Mat4& m, const std::string& node) {
    bool ok = false;
    const Mat4 inv = inverse(m, &ok);
    if (!ok) {
      ++singular_;
      return;
    }
    out_.instances.push_back({proto, Transform(m, inv), node, {}});
  }

  // Applies a node transform to a mesh that only that node uses.
  static void bake(TriangleMesh& tm, const Mat4& m) {
    if (m == Mat4::identity()) return;
    const Transform xf(m);
    for (Vec3f& p : tm.positions) p = Vec3f(xf.point(Vec3(p)));
    for (Vec3f& n : tm.normals) n = Vec3f(normalize(xf.normal(Vec3(n))));
    // A mirroring transform flips the winding-derived normal; swap two corners so the front
    // side stays the one the shading normals point to.
    if (xf.swaps_handedness())
      for (size_t t = 0; t < tm.triangle_count(); ++t)
        std::swap(tm.indices[3 * t + 1], tm.indices[3 * t + 2]);
  }

  std::optional<TriangleMesh> convert_mesh(unsigned index) {
    const aiMesh& am = *s_.mMeshes[index];
    if (!(am.mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) {
      ++skipped_meshes_;
      return std::nullopt;
    }
    TriangleMesh tm;
    const std::string& name = index < mesh_names_.size() ? mesh_names_[index] : "";
    tm.name = !name.empty() ? name : fmt::format("{} mesh {}", stem_, index);
    tm.positions.resize(am.mNumVertices);
    for (unsigned v = 0; v < am.mNumVertices; ++v)
      tm.positions[v] = {am.mVertices[v].x, am.mVertices[v].y, am.mVertices[v].z};
    if (am.HasNormals()) {
      tm.normals.resize(am.mNumVertices);
      for (unsigned v = 0; v < am.mNumVertices; ++v)
        tm.normals[v] = {am.mNormals[v].x, am.mNormals[v].y, am.mNormals[v].z};
    }
    if (am.HasTextureCoords(0)) {
      tm.uvs.resize(am.mNumVertices);
      for (unsigned v = 0; v < am.mNumVertices; ++v)
        tm.uvs[v] = {am.mTextureCoords[0][v].x, 1.0f - am.mTextureCoords[0][v].y};
    }
    tm.indices.reserve(size_t(am.mNumFaces) * 3);
    for (unsigned f = 0; f < am.mNumFaces; ++f) {
      const aiFace& face = am.mFaces[f];
      if (face.mNumIndices != 3) continue;  // stray points/lines in a mixed mesh
      tm.indices.insert(tm.indices.end(), face.mIndices, face.mIndices + 3);
    }
    tm.material = material(am.mMaterialIndex);
    check_mesh(tm, repairs_);
    if (tm.indices.empty()) return std::nullopt;
    if (tm.normals.empty()) generate_normals(tm, kCreaseDegrees);
    return tm;
  }

  uint32_t material(unsigned index) {
    if (index >= s_.mNumMaterials)
      throw LoadError(fmt::format("mesh names material {} of {}", index, s_.mNumMaterials));
    int& slot = material_index_[index];
    if (slot < 0) {
      out_.materials.push_back(convert_material(*s_.mMaterials[index]));
      slot = int(out_.materials.size() - 1);
    }
    return uint32_t(slot);
  }

  std::unique_ptr<Material> convert_material(const aiMaterial& am) {
    auto owned = std::make_unique<WhittedMaterial>();
    WhittedMaterial& mat = *owned;
    aiString name;
    am.Get(AI_MATKEY_NAME, name);
    mat.name = name.C_Str();
    if (mat.name.empty() || mat.name == AI_DEFAULT_MATERIAL_NAME) {
      mat.name = "default";
      return owned;
    }
    aiColor3D c;
    Color kd = mat.base_color.value;
    if (am.Get(AI_MATKEY_COLOR_DIFFUSE, c) == AI_SUCCESS) kd = to_color(c);
    mat.base_color = texture(am, aiTextureType_DIFFUSE, true, kd);
    if (am.Get(AI_MATKEY_COLOR_SPECULAR, c) == AI_SUCCESS) mat.specular = to_color(c);
    float f = 0;
    if (am.Get(AI_MATKEY_SHININESS, f) == AI_SUCCESS && f > 0) mat.exponent = f;
    if (am.Get(AI_MATKEY_REFRACTI, f) == AI_SUCCESS && f > 0 && f != 1) mat.ior = f;
    if (am.Get(AI_MATKEY_OPACITY, f) == AI_SUCCESS && f >= 0 && f < 1) mat.transmission = 1 - f;
    int illum = 0;
    if (am.Get("$mat.illum", 0, 0, illum) == AI_SUCCESS && illum >= 3 && illum <= 7)
      mat.reflectivity = max_component(mat.specular);

    Color ke{0, 0, 0};
    if (am.Get(AI_MATKEY_COLOR_EMISSIVE, c) == AI_SUCCESS) ke = to_color(c);
    if (is_obj_ && max_component(ke) <= 0 && am.Get(AI_MATKEY_COLOR_AMBIENT, c) == AI_SUCCESS &&
        max_component(to_color(c)) > 1) {
      ke = to_color(c);
      warnings_.add(
          fmt::format("{}: material '{}' has no Ke and Ka {} {} {} > 1: read as "
                      "emission",
                      file_, mat.name, c.r, c.g, c.b));
    }
    const bool has_map = am.GetTextureCount(aiTextureType_EMISSIVE) > 0;
    if (max_component(ke) > 0 || has_map)
      // A black Ke beside an emission map would switch the map off; read it as white then.
      mat.emission =
          texture(am, aiTextureType_EMISSIVE, true, max_component(ke) > 0 ? ke : Color{1, 1, 1});
    const Texture normals = texture(am, aiTextureType_NORMALS, false, {1, 1, 1});
    if (normals.kind == Texture::Kind::Image) {
      mat.normal_map = normals;
      mat.has_normal_map = true;
    }
    return owned;
  }

  // The material's first texture of `type` (value multiplies it), or a constant `value`.
  Texture texture(const aiMaterial& am, aiTextureType type, bool srgb, Color value) {
    aiString path;
    aiTextureMapMode modes[3] = {aiTextureMapMode_Wrap, aiTextureMapMode_Wrap,
                                 aiTextureMapMode_Wrap};
    if (am.GetTextureCount(type) == 0 ||
        am.GetTexture(type, 0, &path, nullptr, nullptr, nullptr, nullptr, modes) != AI_SUCCESS)
      return Texture::constant(value);
    const std::string p = path.C_Str();
    if (!p.empty() && p[0] == '*') {
      warnings_.add(
          fmt::format("{}: embedded texture {} is not supported; its colour is used "
                      "alone",
                      file_, p));
      return Texture::constant(value);
    }
    // MTL files written on Windows use backslashes.
    std::string portable = p;
    std::replace(portable.begin(), portable.end(), '\\', '/');
    fs::path file = portable;
    if (file.is_relative()) file = dir_ / file;
    std::string error;
    const ReadRole role("an image that " + file_ + " uses");
    auto image = images_.get(file, srgb, &error);
    if (!image) {
      warnings_.add(
          fmt::format("{}: texture {} cannot be read ({}); the material's colour is "
                      "used alone",
                      file_, file.string(), error));
      return Texture::constant(value);
    }
    Texture t;
    t.kind = Texture::Kind::Image;
    t.value = value;
    t.image = std::move(image);
    t.wrap_s = to_wrap(modes[0]);
    t.wrap_t = to_wrap(modes[1]);
    return t;
  }

  const aiScene& s_;
  std::vector<std::string> mesh_names_;  // (assbin does not keep them)
  fs::path dir_;
  std::string file_;
  bool is_obj_;
  std::string stem_;
  LoadedModel out_;
  WarningList warnings_;
  MeshRepairs repairs_;
  ImageFileCache images_;
  std::vector<int> material_index_;
  size_t skipped_meshes_ = 0, singular_ = 0;
};

}  // namespace

namespace {

// assimp's answer for `file`, from the loader program, a forked child when there is no program,
// or this process when isolation is off (scene/isolated.h).
// The model's own files (an OBJ's materials) are read by assimp, in the child: confined to the
// folder this thread's reads are confined to (io/read_file.h), or not at all when the model itself
// is not.
std::vector<unsigned char> read_isolated(const fs::path& file, const IsolationLimits& limits) {
  const ConfinedFolder* folder = confining_folder(file);
  const auto answer = [&] {
    const ScopedReadConfinement confined({folder, nullptr, nullptr});
    return assimp_answer(file);
  };
  if (!loaders_isolated()) return answer();
  const std::string helper = loader_helper();
  if (helper.empty()) return run_isolated("assimp", answer, limits);
  std::vector<std::string> args = {"assimp", file.string()};
  if (folder) args.insert(args.end(), {"--beneath", folder->path().string()});
  return run_helper("assimp", helper, args, limits, folder ? folder->fd() : -1);
}

// Text formats end with a line break; one that ends inside a line was most likely cut short.
bool ends_with_newline(const fs::path& file) {
  const std::string last = read_file_part(file, kModelInput, 1, 1, true);
  return last.empty() || last[0] == '\n';
}

// Takes the last list of strings off the end of the child's answer (assimp_child.h).
std::vector<std::string> pop_strings(std::vector<unsigned char>& answer) {
  uint64_t names = 0;
  if (answer.size() < sizeof names) throw LoadError("the loader's answer is cut short");
  std::memcpy(&names, answer.data() + answer.size() - sizeof names, sizeof names);
  if (names > answer.size() - sizeof names) throw LoadError("the loader's answer is damaged");
  const size_t dump = answer.size() - sizeof names - names;
  std::vector<std::string> out;
  for (size_t at = dump; at < dump + names;) {
    const auto* p = reinterpret_cast<const char*>(answer.data() + at);
    out.emplace_back(p, strnlen(p, dump + names - at));
    at += out.back().size() + 1;
  }
  answer.resize(dump);
  return out;
}

}  // namespace

LoadedModel load_with_assimp(const fs::path& file) {
  const uint64_t size = require_readable(file, kModelInput);
  try {
    if (lowercase_extension(file) == ".ply") check_ply_counts(file);
    std::vector<unsigned char> answer = read_isolated(file, loader_limits(size));
    const std::vector<std::string> opened = pop_strings(answer);
    std::vector<std::string> mesh_names = pop_strings(answer);
    {
      const ReadRole role("a file that " + file.string() + " uses");
      for (const std::string& path : opened) note_read(path);
    }
    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFileFromMemory(answer.data(), answer.size(), 0, "assbin");
    if (!scene)
      throw LoadError(
          fmt::format("cannot read the loader's answer: {}", importer.GetErrorString()));
    LoadedModel model = AssimpBuilder(*scene, file, std::move(mesh_names)).build();
    if (lowercase_extension(file) == ".obj" && !ends_with_newline(file))
      model.warnings.push_back(
          fmt::format("{}: ends in the middle of a line (cut short?); the model is what could be "
                      "read",
                      file.string()));
    return model;
  } catch (const LoadError& e) {
    throw LoadError(file.string() + ": " + e.what());
  }
}

}  // namespace anamorph
