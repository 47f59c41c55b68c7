#include "app/render_outputs.h"

#include <fmt/format.h>

#include <cctype>

#include "app/output_guard.h"
#include "io/image_sink.h"
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
  // (in the first output kind: PNG)
  return (fs::path("out") / (stem + sink_kinds().front()->extensions.front())).string();
}

fs::path coin_overlay_file(const fs::path& out) {
  return fs::path(out).replace_extension(".coins.png");
}

std::vector<std::pair<fs::path, std::string>> render_output_files(const RenderOutputs& o) {
  std::vector<std::pair<fs::path, std::string>> files;
  const std::string main = o.default_output
                               ? fmt::format("the default output {} (no -o given)", o.out.string())
                               : fmt::format("-o {}", o.out.string());
  files.emplace_back(o.out, main + o.frame);
  const auto beside = [&](const fs::path& p, const std::string& what) {
    files.emplace_back(p,
                       fmt::format("{} {} (written beside {}){}", what, p.string(), main, o.frame));
  };
  // The layers the output's format cannot hold go to a file of a format that can: "the AOVs' EXR".
  const std::vector<fs::path> written = output_files(o.out, o.layers);
  std::string second;
  if (written.size() > 1)
    for (char c : sink_kind(written[1]).name)
      second += char(std::toupper(static_cast<unsigned char>(c)));
  if (written.size() > 1) beside(written[1], "the AOVs' " + second);
  if (o.coins_overlay) {
    beside(coin_overlay_file(o.out), "the coin overlay");
  } else {
    // The image so far, when the render is interrupted.
    for (size_t i = 0; i < written.size(); ++i)
      beside(FrameOutput::with_suffix(written[i], ".partial"),
             i == 0 ? "the image so far" : "the AOVs so far");
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
