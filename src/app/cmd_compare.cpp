// `anamorph compare`: error metrics between two images (a render and a reference).
#include <fmt/format.h>

#include "app/common.h"
#include "io/image_io.h"
#include "render/image_metrics.h"

namespace anamorph::app {

namespace {

struct CompareArgs {
  std::string a, b;
};

int run(const CompareArgs& args) {
  const Image a = read_image(args.a), b = read_image(args.b);
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
