// `anamorph warp`: an image made elsewhere (an equirect render, fisheye footage, a cubemap)
// reprojected through the scene's camera without rendering: each pixel's ray direction is
// looked up in the source projection and the image filtered there by the ray's footprint
// (app/source_texture.h). Exit codes as for render.
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <cmath>
#include <filesystem>

#include "app/common.h"
#include "app/output_guard.h"
#include "app/source_texture.h"
#include "app/stmap_options.h"
#include "camera/stmap.h"
#include "io/image_io.h"
#include "math/parallel.h"
#include "params/params.h"

namespace anamorph::app {

namespace {

struct WarpArgs {
  SceneOptions scene;
  std::string input, source, output, filter = "aniso";
};

// The input's size fits the projection: width / height within half a pixel of its aspect.
void check_input_aspect(const SourceProjection& source, const Image& img, const std::string& name) {
  const double want = source.aspect(), have = double(img.width) / img.height;
  if (std::abs(img.width - want * img.height) > 0.5)
    throw ParamError("--source",
                     fmt::format("{} is {}x{} (aspect {:.6g}), but --source {} needs "
                                 "an aspect of {:.6g} (width / height)",
                                 name, img.width, img.height, have, source.describe(), want));
}

OutputImage warp_image(const Camera& camera, const SourceProjection& source,
                       const SourceTexture& texture, int W, int H) {
  OutputImage out;
  out.width = W, out.height = H;
  ImageLayer rgba{"", {"R", "G", "B", "A"}, {}};
  rgba.data.assign(size_t(W) * size_t(H) * 4, 0.0f);
  parallel_for_each(0, H, [&](int y) {
    for (int x = 0; x < W; ++x) {
      const auto r = camera.generate(CameraSample{{(x + 0.5) / W, (y + 0.5) / H}});
      if (!r) continue;
      const auto f = source_footprint(source, *r, W, H);
      if (!f) continue;
      texture.lookup(f->uv, f->duv_dx, f->duv_dy, &rgba.data[(size_t(y) * W + size_t(x)) * 4]);
    }
  });
  out.layers.push_back(std::move(rgba));
  return out;
}

int run_warp(const WarpArgs& a) {
  namespace fs = std::filesystem;
  const fs::path out = a.output;
  if (out.extension() != ".png" && out.extension() != ".exr") {
    print_error(fmt::format("-o {}: use .png or .exr", a.output));
    return kBadInput;
  }
  const TextureFilter filter = a.filter == "bilinear"  ? TextureFilter::Bilinear
                               : a.filter == "bicubic" ? TextureFilter::Bicubic
                                                       : TextureFilter::Aniso;
  // Every output checked against every input before anything is read.
  std::vector<FileRead> inputs = scene_file_input(a.scene.scene);
  inputs.push_back({a.input, "the input image"});
  const std::vector<std::pair<fs::path, std::string>> outputs{{out, "-o " + a.output}};
  check_outputs(inputs, outputs);
  set_interrupt_note(a.output + " not written");
  const Scene s = load(a.scene);
  check_outputs(s.inputs, outputs);
  const int W = s.render.width, H = s.render.height;
  central_origin(*s.camera, W, H);
  const Image image = read_image(a.input);
  const std::unique_ptr<SourceProjection> source =
      parse_source(a.source, double(image.width) / image.height);
  check_input_aspect(*source, image, a.input);
  const SourceTexture texture(image, source->wraps_u(), filter);
  OutputImage img = warp_image(*s.camera, *source, texture, W, H);
  img.metadata["anamorph.command"] = command_line();
  img.metadata["anamorph.camera"] = s.camera->describe() + "\n" + s.camera_toml;
  write_image(out, img);
  return kOk;
}

}  // namespace

void add_warp(CLI::App& app, std::function<int()>& runner) {
  auto a = std::make_shared<WarpArgs>();
  CLI::App* cmd = app.add_subcommand(
      "warp",
      "Reproject an image (PNG, JPEG, EXR, HDR) in a source projection through the scene's "
      "camera, without rendering (docs/compositing.md)");
  a->scene.add_to(*cmd);
  cmd->add_option("input", a->input, "Input image")->required();
  cmd->add_option("--source", a->source, source_option_help())->required();
  cmd->add_option("-o,--output", a->output, "Output image (.png or .exr)")->required();
  cmd->add_option("--filter", a->filter,
                  "aniso (default: OpenImageIO's anisotropic MIP-map filter over each pixel's "
                  "footprint), bilinear or bicubic (no MIP-maps: point lookups, as an STMap node)")
      ->check(CLI::IsMember({"aniso", "bilinear", "bicubic"}));
  cmd->callback(
      [a, &runner] { runner = [a] { return guard_stmap_errors([a] { return run_warp(*a); }); }; });
}

}  // namespace anamorph::app
