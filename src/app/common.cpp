#include "app/common.h"

#include "dist/world.h"

#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <new>
#include <sstream>

#include <toml++/toml.h>

#include "app/output_guard.h"
#include "io/image_io.h"
#include "math/user_text.h"
#include "render/checkpoint.h"
#include "render/memory_estimate.h"
#include "scene/loaders.h"
#include "scene/scene_loader.h"
#include "scene/toml_reader.h"

namespace anamorph::app {

namespace {
std::string g_command_line;
std::vector<std::string> g_args;
}  // namespace

void set_command_line(int argc, char** argv) {
  g_args.assign(argv + std::min(argc, 1), argv + argc);
  for (int i = 0; i < argc; ++i) {
    std::string a = argv[i];
    const bool quote = a.find_first_of(" \t\"'") != std::string::npos;
    g_command_line += (i ? " " : "") + (quote ? "'" + a + "'" : a);
  }
}
std::string command_line() { return g_command_line; }
const std::vector<std::string>& command_args() { return g_args; }
void set_command_args(std::vector<std::string> args) { g_args = std::move(args); }

void SceneOptions::add_to(CLI::App& cmd, bool required) {
  cmd.add_option("scene", scene, "Scene file (TOML)")->required(required);
  cmd.add_option("--width", width, "Image width in pixels (overrides image.width)")
      ->check(CLI::Range(1, 65536));
  cmd.add_option("--height", height, "Image height in pixels (overrides image.height)")
      ->check(CLI::Range(1, 65536));
  cmd.add_option("--camera", camera,
                 "A camera preset (e.g. fisheye) at the scene's camera, or the index of a glTF "
                 "camera: camera.preset=NAME or camera.gltf_camera=N");
  cmd.add_option("--env", env,
                 "The environment: a colour (0.05 or 0.1,0.2,0.3: environment.color) or an "
                 "equirectangular image file (environment.file)");
  cmd.add_option("--set", set,
                 "Override any scene key by its dotted path, e.g. --set camera.fov=90 (repeatable)")
      ->take_all();
}

namespace {

// v as a TOML string (quoted, escaped).
std::string toml_string(const std::string& v) {
  std::ostringstream os;
  os << toml::value<std::string>(v);
  return os.str();
}

bool all_of_chars(const std::string& s, std::string_view allowed) {
  return !s.empty() && s.find_first_not_of(allowed) == std::string::npos;
}

// --camera N (a glTF camera) or --camera PRESET.
std::string camera_override(const std::string& v) {
  if (all_of_chars(v, "0123456789")) return "camera.gltf_camera=" + v;
  return "camera.preset=" + toml_string(v);
}

// --env 0.05, --env 0.1,0.2,0.3 or --env sky.hdr (relative to the working directory).
std::string env_override(const std::string& v) {
  if (all_of_chars(v, "0123456789.,eE+- ")) {
    const bool rgb = v.find(',') != std::string::npos;
    return "environment.color=" + (rgb ? "[" + v + "]" : v);
  }
  return "environment.file=" + toml_string(std::filesystem::absolute(v).string());
}

}  // namespace

std::vector<std::string> SceneOptions::overrides() const {
  std::vector<std::string> o;
  if (width) o.push_back(fmt::format("image.width={}", *width));
  if (height) o.push_back(fmt::format("image.height={}", *height));
  if (camera) o.push_back(camera_override(*camera));
  if (env) o.push_back(env_override(*env));
  o.insert(o.end(), set.begin(), set.end());
  return o;
}

namespace {

// The options' overrides, then the command's own; the loaded scene's warnings printed.
std::vector<std::string> with_extra(const SceneOptions& o, const std::vector<std::string>& extra) {
  std::vector<std::string> ov = o.overrides();
  ov.insert(ov.end(), extra.begin(), extra.end());
  return ov;
}

// A worker rank of an MPI job loads the head's scene: only the head prints its warnings.
Scene warned(Scene s) {
  if (dist::World::rank() == 0)
    for (const auto& w : s.warnings) print_warning(w);
  return s;
}

}  // namespace

Scene load(const SceneOptions& o, const std::vector<std::string>& extra, double frame) {
  return warned(load_scene(o.scene, with_extra(o, extra), frame));
}

void load_view_into(const SceneOptions& o, const std::vector<std::string>& extra, double frame,
                    Scene& loaded) {
  Scene v = warned(load_view(o.scene, with_extra(o, extra), frame, loaded));
  loaded.render = v.render;
  loaded.camera = std::move(v.camera);
  loaded.camera_toml = std::move(v.camera_toml);
  loaded.effective_toml = std::move(v.effective_toml);
  loaded.frame = frame;
  loaded.shutter_open = v.shutter_open;
  loaded.shutter_close = v.shutter_close;
  loaded.inputs.insert(loaded.inputs.end(), v.inputs.begin(), v.inputs.end());
}

void attach_next_frame(const SceneOptions& o, const std::vector<std::string>& extra,
                       const std::vector<Aov>& aovs, Scene& scene) {
  const auto motion = [&](double frame) {
    if (animates_view_only(scene))
      return frame_motion(load_view(o.scene, with_extra(o, extra), frame, scene), &scene);
    return frame_motion(load_scene(o.scene, with_extra(o, extra), frame));
  };
  scene.next = aovs_need_frame(aovs, 1) ? motion(scene.frame + 1) : nullptr;
  scene.previous = aovs_need_frame(aovs, -1) ? motion(scene.frame - 1) : nullptr;
}

void print_error(const std::string& message) {
  fmt::print(stderr, "error: {}\n", printable(message));
}
void print_warning(const std::string& message) {
  fmt::print(stderr, "warning: {}\n", printable(message));
}

int run_guarded(const std::function<int()>& body) {
  try {
    return body();
  } catch (const SceneError& e) {
    print_error(e.what());
    return kBadInput;
  } catch (const LoadError& e) {
    print_error(e.what());
    return kBadInput;
  } catch (const ImageReadError& e) {
    print_error(e.what());
    return kBadInput;
  } catch (const CheckpointError& e) {
    print_error(e.what());
    return kBadInput;
  } catch (const OutputClash& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kBadInput;
  } catch (const ImageIoError& e) {
    print_error(e.what());
    return kFailure;
  } catch (const std::bad_alloc&) {
    // What the up-front estimate did not foresee (a scene's models, another process's growth).
    fmt::print(stderr, "error: out of memory (the machine has {} available now)\n",
               format_bytes(available_memory()));
    return kFailure;
  } catch (const std::exception& e) {
    print_error(e.what());
    return kFailure;
  }
}

int flush_standard_output(int code) {
  if (std::fflush(stdout) == 0 && !std::ferror(stdout)) return code;
  const int e = errno;
  // (fputs: stderr may be broken too, and fmt::print would throw from here.)
  std::fputs("error: cannot write to standard output: ", stderr);
  std::fputs(e ? std::strerror(e) : "a write failed", stderr);
  std::fputs("\n", stderr);
  return code == kOk ? kFailure : code;
}

}  // namespace anamorph::app
