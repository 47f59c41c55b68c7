#include "app/render_outputs.h"

#include <fmt/format.h>

#include <cctype>

#include "app/output_guard.h"
#include "render/frame_output.h"

namespace anamorph::app {

namespace fs = std::filesystem;

std::string default_render_output(const fs::path& scene, bool frames) {
  std::string stem = scene.stem().string();
  if (frames) {  // (a printf pattern: a % in the name is written %%)
    std::string escaped;
    for (char c : stem) escaped += c == '%' ? std::string("%%") : std::string(1, c);
    stem = escaped + "_%04d";
  }
  return (fs::path("out") / (stem + ".png")).string();
}

std::string render_format(const fs::path& out) {
  std::string ext = out.extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".png" || ext == ".exr") return ext;
  return ext.empty() && written_directly(out) ? ".png" : "";
}

std::vector<std::pair<fs::path, std::string>> render_output_files(const RenderOutputs& o) {
  std::vector<std::pair<fs::path, std::string>> files;
  const std::string main = o.default_output
                               ? fmt::format("the default output {} (no -o given)", o.out.string())
                               : fmt::format("-o {}", o.out.string());
  files.emplace_back(o.out, main + o.frame);
  const bool png = render_format(o.out) == ".png";
  const auto beside = [&](const fs::path& p, const char* what) {
    files.emplace_back(p,
                       fmt::format("{} {} (written beside {}){}", what, p.string(), main, o.frame));
  };
  fs::path exr = o.out;
  exr.replace_extension(".exr");
  if (png && (o.aovs || o.coins_overlay)) beside(exr, "the AOVs' EXR");
  if (o.coins_overlay) {
    fs::path marked = o.out;
    beside(marked.replace_extension(".coins.png"), "the coin overlay");
  } else {
    // The image so far, when the render is interrupted.
    beside(FrameOutput::with_suffix(o.out, ".partial"), "the image so far");
    if (png && o.aovs) beside(FrameOutput::with_suffix(exr, ".partial"), "the AOVs so far");
  }
  if (!o.checkpoint.empty())
    files.emplace_back(o.checkpoint,
                       fmt::format("--checkpoint {}{}", o.checkpoint.string(), o.frame));
  if (!o.stats.empty())
    files.emplace_back(o.stats, fmt::format("--stats {}{}", o.stats.string(), o.frame));
  if (!o.video.empty()) files.emplace_back(o.video, fmt::format("--video {}", o.video.string()));
  return files;
}

void check_render_outputs(const RenderOutputs& o, const std::vector<FileRead>& inputs) {
  check_outputs(inputs, render_output_files(o));
}

}  // namespace anamorph::app
