#include "app/common.h"

#include <fmt/format.h>

#include <cstdio>
#include <exception>

#include "io/image_io.h"
#include "scene/loaders.h"
#include "scene/scene_loader.h"
#include "scene/toml_reader.h"

namespace anamorph::app {

namespace {
std::string g_command_line;
}

void set_command_line(int argc, char** argv) {
  for (int i = 0; i < argc; ++i) {
    std::string a = argv[i];
    const bool quote = a.find_first_of(" \t\"'") != std::string::npos;
    g_command_line += (i ? " " : "") + (quote ? "'" + a + "'" : a);
  }
}
std::string command_line() { return g_command_line; }

void SceneOptions::add_to(CLI::App& cmd) {
  cmd.add_option("scene", scene, "Scene file (TOML)")->required();
  cmd.add_option("--width", width, "Image width in pixels (overrides image.width)")
      ->check(CLI::Range(1, 65536));
  cmd.add_option("--height", height, "Image height in pixels (overrides image.height)")
      ->check(CLI::Range(1, 65536));
  cmd.add_option("--set", set,
                 "Override any scene key by its dotted path, e.g. --set camera.fov=90 (repeatable)")
      ->take_all();
}

std::vector<std::string> SceneOptions::overrides() const {
  std::vector<std::string> o;
  if (width) o.push_back(fmt::format("image.width={}", *width));
  if (height) o.push_back(fmt::format("image.height={}", *height));
  o.insert(o.end(), set.begin(), set.end());
  return o;
}

Scene load(const SceneOptions& o, const std::vector<std::string>& extra, double frame) {
  std::vector<std::string> ov = o.overrides();
  ov.insert(ov.end(), extra.begin(), extra.end());
  Scene s = load_scene(o.scene, ov, frame);
  for (const auto& w : s.warnings) fmt::print(stderr, "warning: {}\n", w);
  return s;
}

void load_view_into(const SceneOptions& o, const std::vector<std::string>& extra, double frame,
                    Scene& loaded) {
  std::vector<std::string> ov = o.overrides();
  ov.insert(ov.end(), extra.begin(), extra.end());
  Scene v = load_view(o.scene, ov, frame, loaded);
  for (const auto& w : v.warnings) fmt::print(stderr, "warning: {}\n", w);
  loaded.render = v.render;
  loaded.camera = std::move(v.camera);
  loaded.camera_toml = std::move(v.camera_toml);
  loaded.frame = frame;
}

int run_guarded(const std::function<int()>& body) {
  try {
    return body();
  } catch (const SceneError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kBadInput;
  } catch (const LoadError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kBadInput;
  } catch (const ImageIoError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kFailure;
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kFailure;
  }
}

}  // namespace anamorph::app
