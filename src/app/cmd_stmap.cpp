// `anamorph stmap`: the scene camera as an STMap to a source projection (camera/stmap.h), for
// Nuke's STMap, Natron's STMapOFX, Blender's Map UV (docs/compositing.md).
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <cmath>
#include <filesystem>

#include "app/common.h"
#include "app/output_guard.h"
#include "app/stmap_options.h"
#include "camera/stmap.h"
#include "io/image_io.h"

namespace anamorph::app {

namespace {

struct StmapArgs {
  SceneOptions scene;
  std::string source, output, source_size;
  bool inverse = false;
  double depth = 0;  // 0: the camera must be central
};

OutputImage map_image(const StMap& m) {
  OutputImage img;
  img.width = m.width, img.height = m.height;
  ImageLayer rgba{"", {"R", "G", "B", "A"}, {}}, dir{"direction", {"X", "Y", "Z"}, m.direction};
  rgba.data.resize(size_t(m.width) * size_t(m.height) * 4);
  for (size_t i = 0; i < m.alpha.size(); ++i) {
    rgba.data[4 * i] = m.st[2 * i];
    rgba.data[4 * i + 1] = m.st[2 * i + 1];
    rgba.data[4 * i + 2] = 0;
    rgba.data[4 * i + 3] = m.alpha[i];
  }
  img.layers = {std::move(rgba), std::move(dir)};
  return img;
}

int run_stmap(const StmapArgs& a) {
  namespace fs = std::filesystem;
  const fs::path out = a.output;
  if (out.extension() != ".exr") {
    print_error(fmt::format("-o {}: an STMap is a 32-bit float EXR, use .exr", a.output));
    return kBadInput;
  }
  std::optional<std::pair<int, int>> size;
  if (!a.source_size.empty()) size = parse_size("--source-size", a.source_size);
  const std::unique_ptr<SourceProjection> source =
      parse_source(a.source, size ? double(size->first) / size->second : 1.0);
  const std::vector<std::pair<fs::path, std::string>> outputs{{out, "-o " + a.output}};
  check_outputs(scene_file_input(a.scene.scene), outputs);
  set_interrupt_note(a.output + " not written");
  const Scene s = load(a.scene);
  check_outputs(s.inputs, outputs);
  const int W = s.render.width, H = s.render.height;
  const std::optional<double> depth = a.depth > 0 ? std::optional(a.depth) : std::nullopt;
  const DepthSphere sphere = map_sphere(*s.camera, W, H, depth);
  OutputImage img;
  if (a.inverse) {
    const int sw = size ? size->first : W;
    const int sh = size ? size->second : std::max(1, int(std::lround(sw / source->aspect())));
    img = map_image(inverse_stmap(*s.camera, sphere, *source, sw, sh));
  } else {
    img = map_image(
        forward_stmap(*s.camera, *source, W, H, depth ? std::optional(sphere) : std::nullopt));
  }
  img.metadata["anamorph.command"] = command_line();
  img.metadata["anamorph.camera"] = s.camera->describe() + "\n" + s.camera_toml;
  img.metadata["anamorph.stmap"] = fmt::format(
      "{} {}: R = s, G = t (from the bottom), A = coverage; direction.XYZ = unit "
      "world direction",
      a.inverse ? "source -> camera" : "camera -> source", source->describe());
  if (depth)
    img.metadata["anamorph.stmap.depth"] = fmt::format(
        "exact at distance {:.17g} from the eye ({:.17g}, {:.17g}, {:.17g}), the mean ray origin",
        sphere.depth, sphere.eye.x, sphere.eye.y, sphere.eye.z);
  write_exr(out, img);
  return kOk;
}

}  // namespace

void add_stmap(CLI::App& app, std::function<int()>& runner) {
  auto a = std::make_shared<StmapArgs>();
  CLI::App* cmd = app.add_subcommand(
      "stmap",
      "Write the camera as an STMap to a source projection: a float EXR, R = s, G = t (from the "
      "bottom), A = 1 where there is a ray, layer direction.XYZ (docs/compositing.md)");
  a->scene.add_to(*cmd);
  cmd->add_option("--source", a->source, source_option_help())->required();
  cmd->add_option("-o,--output", a->output, "Output file (.exr)")->required();
  cmd->add_flag("--inverse", a->inverse,
                "The map the other way: for each source pixel, the camera's image position (alpha "
                "0 where no camera pixel sees its direction)");
  cmd->add_option("--depth", a->depth,
                  "For a camera whose rays leave different points: the distance D at which the map "
                  "is exact (the world taken as a sphere of radius D about the mean ray origin)")
      ->check(CLI::PositiveNumber);
  cmd->add_option(
      "--source-size", a->source_size,
      "WxH of the source image: its aspect for fisheye and perspective sources (default "
      "1), and the size of the --inverse map (default: the scene's width, the height "
      "from the projection's aspect)");
  cmd->callback(
      [a, &runner] { runner = [a] { return guard_stmap_errors([a] { return run_stmap(*a); }); }; });
}

}  // namespace anamorph::app
