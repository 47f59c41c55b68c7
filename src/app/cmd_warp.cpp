// `anamorph warp`: an image made elsewhere (an equirect render, fisheye footage, a cubemap)
// reprojected through the scene's camera without rendering: each pixel's ray direction is
// looked up in the source projection and the image filtered there by the ray's footprint
// (warp/warp_texture.h), the output streamed in strips (app/warp_frame.h). Exit codes as for
// render; an interruption leaves no output file (the sink writes a temporary until commit).
#include <fmt/format.h>
#include <tbb/task_arena.h>
#include <unistd.h>

#include <CLI/CLI.hpp>

#include <cmath>
#include <filesystem>

#include "app/output_guard.h"
#include "app/stmap_options.h"
#include "app/thread_option.h"
#include "app/warp_command.h"
#include "app/warp_frame.h"
#include "camera/stmap.h"
#include "io/image_io.h"
#include "math/parallel.h"
#include "params/params.h"

namespace anamorph::app {

namespace {

// The progress bar on a terminal, unless --quiet.
std::function<void(double)> progress_bar(const WarpArgs& a, const std::string& prefix) {
  if (a.quiet || !isatty(STDERR_FILENO)) return nullptr;
  return [prefix](double f) {
    const int width = 30, filled = int(f * width);
    fmt::print(stderr, "\r{}[{}{}] {:5.1f}%{}", prefix, std::string(size_t(filled), '#'),
               std::string(size_t(width - filled), ' '), 100 * f, f >= 1 ? "\n" : "");
  };
}

int warp_single(const WarpArgs& a) {
  namespace fs = std::filesystem;
  std::vector<FileRead> inputs = scene_file_input(a.scene.scene);
  inputs.push_back({a.input, "the input image"});
  const std::vector<std::pair<fs::path, std::string>> outputs{{a.output, "-o " + a.output}};
  check_outputs(inputs, outputs);
  set_interrupt_note(a.output + " not written");
  const Scene s = load(a.scene);
  check_outputs(s.inputs, outputs);
  warp_frame(a, s, a.input, a.output, "", [&] { set_interrupt_note(a.output + " was written"); });
  return kOk;
}

int run_warp(const WarpArgs& a) {
  const std::filesystem::path out = a.output;
  if (out.extension() != ".png" && out.extension() != ".exr") {
    print_error(fmt::format("-o {}: use .png or .exr", a.output));
    return kBadInput;
  }
  tbb::task_arena arena(arena_concurrency(a.threads.value_or(0)));
  int rc = kOk;
  arena.execute([&] {
    rc = guard_stmap_errors([&] { return a.frames.empty() ? warp_single(a) : warp_sequence(a); });
  });
  return rc;
}

}  // namespace

void warp_frame(const WarpArgs& a, const Scene& s, const std::filesystem::path& input,
                const std::filesystem::path& output, const std::string& prefix,
                const std::function<void()>& committed) {
  const int W = s.render.width, H = s.render.height;
  central_origin(*s.camera, W, H);
  Image image = read_image(input);
  const std::unique_ptr<SourceProjection> source =
      parse_source(a.source, double(image.width) / image.height);
  check_source_aspect(*source, image.width, image.height, input.string());
  // (the image moves into the texture: the in-memory filters keep it as their level 0)
  const std::unique_ptr<WarpTexture> texture = make_warp_texture(
      std::move(image), source->wraps_u(),
      texture_filter_named(a.filter).value_or(TextureFilter::Area), a.threads.value_or(0));
  std::map<std::string, std::string> metadata{
      {"anamorph.command", command_line()},
      {"anamorph.camera", s.camera->describe() + "\n" + s.camera_toml},
      {"anamorph.warp", fmt::format("{} from {}", input.filename().string(), source->describe())}};
  warp_to_file({*s.camera, *source, *texture, W, H}, output, metadata, progress_bar(a, prefix),
               committed);
}

void add_warp(CLI::App& app, std::function<int()>& runner) {
  auto a = std::make_shared<WarpArgs>();
  CLI::App* cmd = app.add_subcommand(
      "warp",
      "Reproject an image (PNG, JPEG, EXR, HDR) or a numbered sequence in a source projection "
      "through the scene's camera, without rendering (docs/compositing.md)");
  a->scene.add_to(*cmd);
  cmd->add_option("input", a->input,
                  "Input image; with --frames a printf pattern (in/frame_%04d.exr)")
      ->required();
  cmd->add_option("--source", a->source, source_option_help())->required();
  cmd->add_option("-o,--output", a->output,
                  "Output image (.png or .exr); with --frames a printf pattern")
      ->required();
  cmd->add_option("--filter", a->filter,
                  "area (default: bilinear where a pixel's footprint in the source is within a "
                  "texel, an average along the footprint over MIP levels where the source is "
                  "minified), bilinear (the 4 nearest texels, as an STMap node), aniso "
                  "(OpenImageIO's anisotropic MIP filter) or bicubic (OpenImageIO's B-spline)")
      ->check(CLI::IsMember({"area", "bilinear", "aniso", "bicubic"}));
  cmd->add_option("--frames", a->frames,
                  "FIRST:LAST: warp each frame of a sequence (INPUT and -o are printf patterns), "
                  "the scene's [[animate]] keys at that frame");
  cmd->add_option("--threads", a->threads, "Worker threads (default: all cores)")
      ->check(thread_count_check());
  cmd->add_flag("-q,--quiet", a->quiet, "No progress bar");
  cmd->callback([a, &runner] { runner = [a] { return run_warp(*a); }; });
}

}  // namespace anamorph::app
