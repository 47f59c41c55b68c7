// `anamorph compare`: error metrics between two images (a render and a reference).
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <cmath>
#include <utility>

#include "app/common.h"
#include "io/image_io.h"
#include "render/image_metrics.h"

namespace anamorph::app {

namespace {

struct CompareArgs {
  std::string a, b;
};

// "" when every RGB value of `img` is finite, else which are not (an EXR may hold inf or NaN:
// the metrics over it would be too, and are not printed).
std::string non_finite(const Image& img, const std::string& name) {
  size_t count = 0, first = 0;
  for (size_t i = 0; i < img.pixels.size(); ++i)
    if (int(i % size_t(img.channels)) < 3 && !std::isfinite(img.pixels[i]) && count++ == 0)
      first = i;
  if (count == 0) return "";
  const size_t pixel = first / size_t(img.channels);
  return fmt::format(
      "{}: {} colour values are not finite numbers, the first at pixel ({}, {}) channel {}: {}; "
      "the metrics would be meaningless",
      name, count, pixel % size_t(img.width), pixel / size_t(img.width),
      "RGB"[first % size_t(img.channels)], img.pixels[first]);
}

int run(const CompareArgs& args) {
  const Image a = read_image(args.a), b = read_image(args.b);
  for (const auto& [img, name] : {std::pair{&a, &args.a}, std::pair{&b, &args.b}})
    if (const std::string why = non_finite(*img, *name); !why.empty()) {
      print_error(why);
      return kBadInput;
    }
  if (a.width != b.width || a.height != b.height) {
    print_error(fmt::format("sizes differ: {} is {}x{}, {} is {}x{}", args.a, a.width, a.height,
                            args.b, b.width, b.height));
    return kBadInput;
  }
  const ImageMetrics m = compare_images(a.pixels, b.pixels, a.width, a.height);
  fmt::print(
      "rmse {:.6g}\nrmse_display {:.6g}\nmean_abs {:.6g}\nmean_relative {:.6g}\nssim {:.6f}\n",
      m.rmse, m.rmse_display, m.mean_abs, m.mean_relative, m.ssim);
  return kOk;
}

}  // namespace

void add_compare(CLI::App& app, std::function<int()>& runner) {
  auto a = std::make_shared<CompareArgs>();
  CLI::App* cmd = app.add_subcommand(
      "compare",
      "Print RMSE, mean absolute and relative difference and SSIM between two images (PNG or EXR)");
  cmd->add_option("image", a->a, "Image to judge")->required()->check(CLI::ExistingFile);
  cmd->add_option("reference", a->b, "Reference image")->required()->check(CLI::ExistingFile);
  cmd->callback([a, &runner] { runner = [a] { return run(*a); }; });
}

}  // namespace anamorph::app
