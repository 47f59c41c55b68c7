// A scene that reads one file of every kind a run reads (an include, a texture, an environment
// map, a ray table, a glTF model with an external buffer and image), for the tests that no
// output overwrites an input (outputs_test.cpp) and the signal matrix (signals_test.cpp).
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cli_util.h"
#include "io/image_io.h"
#include "test_util.h"

namespace anamorph::test {

// A folder under /tmp removed at the end.
struct ScratchDir {
  std::filesystem::path dir;
  explicit ScratchDir(const std::string& name)
      : dir(std::filesystem::temp_directory_path() /
            ("anamorph_" + name + "_" + std::to_string(getpid()))) {
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
  }
  ~ScratchDir() { std::filesystem::remove_all(dir); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(dir / name, std::ios::binary) << text;
    return (dir / name).string();
  }
};

// A small RGBA PNG (a texture, an environment map).
inline void write_test_png(const std::filesystem::path& file, int seed) {
  Rgba8Image img;
  img.width = img.height = 4;
  for (int i = 0; i < 16; ++i)
    for (int c = 0; c < 4; ++c) img.rgba.push_back((unsigned char)(c == 3 ? 255 : seed * 40 + i));
  write_png(file, img);
}

// One triangle with texture coordinates in tri.bin, a material whose base colour is gtex.png.
inline void write_test_gltf(const std::filesystem::path& dir) {
  const float data[15] = {-1, 0, -1, 1, 0, -1, 0, 0, 1, 0, 0, 1, 0, 0.5f, 1};
  std::ofstream(dir / "tri.bin", std::ios::binary)
      .write(reinterpret_cast<const char*>(data), sizeof data);
  write_test_png(dir / "gtex.png", 3);
  std::ofstream(dir / "tri.gltf")
      << R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
 "nodes": [{"mesh": 0}],
 "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "material": 0}]}],
 "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
 "textures": [{"source": 0}], "images": [{"uri": "gtex.png"}],
 "buffers": [{"uri": "tri.bin", "byteLength": 60}],
 "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                 {"buffer": 0, "byteOffset": 36, "byteLength": 24}],
 "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                "min": [-1, 0, -1], "max": [1, 0, 1]},
               {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"}]}
)";
}

// The scene (scene.toml) and every file it reads, in `dir`. Returns the scene's path; `files`
// gets the other files it reads.
inline std::string write_reading_scene(const std::filesystem::path& dir,
                                       std::vector<std::filesystem::path>* files = nullptr) {
  std::ofstream(dir / "base.toml")
      << "[image]\nwidth = 8\nheight = 8\n[camera]\nlook_from = [0, 1, 4]\n"
         "look_at = [0, 0, 0]\n";
  const CliResult rays =
      run_cli("rays " + (dir / "base.toml").string() + " -o " + (dir / "rays.exr").string());
  if (rays.code != 0) ADD_FAILURE() << "anamorph rays failed: " << rays.out;
  std::filesystem::remove(dir / "base.toml");
  write_test_png(dir / "tex.png", 1);
  write_test_png(dir / "env.png", 2);
  write_test_gltf(dir);
  std::ofstream(dir / "tri.obj")
      << "mtllib tri.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n";
  std::ofstream(dir / "tri.mtl") << "newmtl red\nKd 1 0 0\n";
  std::ofstream(dir / "inc.toml")
      << "[[light]]\ntype = \"point\"\nposition = [2, 3, 2]\nintensity = 10\n";
  std::ofstream(dir / "scene.toml")
      << "include = \"inc.toml\"\n[image]\nwidth = 8\nheight = 8\n"
         "[render]\nantialias = \"uniform\"\n"
         "[camera.org]\ntype = \"table\"\nfile = \"rays.exr\"\n"
         "[camera.dir]\ntype = \"table\"\nfile = \"rays.exr\"\n"
         "[environment]\nfile = \"env.png\"\n"
         "[[material]]\nname = \"tex\"\ncolor = { type = \"image\", file = \"tex.png\" }\n"
         "[[object]]\ntype = \"sphere\"\nmaterial = \"tex\"\n"
         "[[object]]\ntype = \"mesh\"\nfile = \"tri.gltf\"\n"
         "[[object]]\ntype = \"mesh\"\nfile = \"tri.obj\"\n";
  if (files)
    for (const char* f : {"inc.toml", "rays.exr", "env.png", "tex.png", "tri.gltf", "tri.bin",
                          "gtex.png", "tri.obj", "tri.mtl"})
      files->push_back(dir / f);
  return (dir / "scene.toml").string();
}

// Temporary files (".NAME.tmp-PID-...", or any "*.tmp-*") left in `dir` and below.
inline std::vector<std::string> temporaries_in(const std::filesystem::path& dir) {
  std::vector<std::string> left;
  std::error_code ec;
  for (auto it = std::filesystem::recursive_directory_iterator(dir, ec);
       it != std::filesystem::recursive_directory_iterator(); it.increment(ec))
    if (it->path().filename().string().find(".tmp-") != std::string::npos)
      left.push_back(it->path().string());
  return left;
}

}  // namespace anamorph::test
