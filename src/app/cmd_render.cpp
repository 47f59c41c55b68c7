// `anamorph render`: render a scene to PNG or EXR.
#include <fmt/format.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <filesystem>

#include "app/common.h"
#include "io/image_io.h"
#include "render/renderer.h"

namespace anamorph::app {

namespace {

struct RenderArgs {
  SceneOptions scene;
  std::string output;
  std::optional<int> spp, threads;
  std::optional<int64_t> seed;
  std::optional<std::string> integrator, sampler;
  std::string aovs;
  bool quiet = false;
};

std::atomic<bool> g_cancel{false};
void on_sigint(int) { g_cancel = true; }

void print_progress(const Progress& p) {
  const int width = 30;
  const int filled = int(p.fraction * width);
  const double mrays = p.seconds > 0 ? p.rays / p.seconds * 1e-6 : 0;
  const double eta = p.fraction > 0 ? p.seconds * (1 - p.fraction) / p.fraction : 0;
  fmt::print(stderr, "\r[{}{}] {:5.1f}%  {:7.2f} Mrays/s  ETA {:.0f}s   ", std::string(size_t(filled), '#'),
             std::string(size_t(width - filled), ' '), 100 * p.fraction, mrays, eta);
}

int run(const RenderArgs& a) {
  std::vector<std::string> extra;
  if (a.spp) extra.push_back(fmt::format("render.spp={}", *a.spp));
  if (a.seed) extra.push_back(fmt::format("render.seed={}", *a.seed));
  if (a.integrator) extra.push_back(fmt::format("render.integrator=\"{}\"", *a.integrator));
  if (a.sampler) extra.push_back(fmt::format("render.sampler=\"{}\"", *a.sampler));
  std::vector<Aov> aovs;
  try {
    aovs = parse_aovs(a.aovs);
  } catch (const std::invalid_argument& e) {
    fmt::print(stderr, "error: --aov: {}\n", e.what());
    return kBadInput;
  }
  namespace fs = std::filesystem;
  const fs::path out = a.output.empty() ? fs::path(fs::path(a.scene.scene).stem().string() + ".png") : fs::path(a.output);
  std::string ext = out.extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (ext != ".png" && ext != ".exr") {
    fmt::print(stderr, "error: -o {}: unsupported image format (use .png or .exr)\n", out.string());
    return kBadInput;
  }

  const Scene scene = load(a.scene, extra);
  const Renderer renderer(scene);
  Film film(scene.render.width, scene.render.height, aovs);
  RenderOptions opt;
  opt.threads = a.threads.value_or(0);
  opt.aovs = aovs;
  opt.cancel = &g_cancel;
  const bool bar = !a.quiet && isatty(STDERR_FILENO);
  auto last = std::chrono::steady_clock::now();
  if (bar)
    opt.on_progress = [&](const Progress& p) {
      const auto now = std::chrono::steady_clock::now();
      if (now - last < std::chrono::milliseconds(100) && p.fraction < 1) return;
      last = now;
      print_progress(p);
    };
  std::signal(SIGINT, on_sigint);
  std::signal(SIGTERM, on_sigint);
  const RenderStats st = renderer.render(film, opt);
  if (bar) fmt::print(stderr, "\r{}\r", std::string(80, ' '));
  if (st.cancelled) {
    fmt::print(stderr, "interrupted: nothing written\n");
    return kFailure;
  }

  OutputImage img = film.output();
  img.metadata["anamorph.version"] = ANAMORPH_VERSION;
  img.metadata["anamorph.command"] = command_line();
  img.metadata["anamorph.scene"] = scene.path;
  img.metadata["anamorph.camera"] = scene.camera->describe() + "\n" + scene.camera_toml;
  if (ext == ".png") {
    write_png(out, img);
    if (!aovs.empty()) {
      fs::path exr = out;
      exr.replace_extension(".exr");
      write_exr(exr, img);
      if (!a.quiet) fmt::print("AOVs written to {}\n", exr.string());
    }
  } else {
    write_exr(out, img);
  }
  if (!a.quiet) {
    const double per_pixel = double(st.samples) / (double(scene.render.width) * scene.render.height);
    const std::string sampling = scene.render.antialias == "adaptive"
                                     ? fmt::format("adaptive, {:.2f} samples/pixel", per_pixel)
                                     : fmt::format("{} spp", scene.render.spp);
    fmt::print("{}: {}x{}, {}, {} in {:.2f} s, {:.2f} Mrays/s ({:.3f} M rays), {} NaN/Inf samples dropped\n",
               out.string(), scene.render.width, scene.render.height, sampling, scene.render.integrator,
               st.seconds, st.mrays_per_second(), st.rays * 1e-6, st.nan_samples);
  }
  if (st.nan_samples > 0)
    fmt::print(stderr, "warning: {} samples had NaN or Inf radiance and were dropped (first at pixel {},{} sample {})\n",
               st.nan_samples, st.nan_x, st.nan_y, st.nan_sample);
  return kOk;
}

}  // namespace

void add_render(CLI::App& app, std::function<int()>& runner) {
  auto a = std::make_shared<RenderArgs>();
  CLI::App* cmd = app.add_subcommand("render", "Render a scene to an image (PNG or EXR)");
  a->scene.add_to(*cmd);
  cmd->add_option("-o,--output", a->output, "Output image (.png or .exr); default <scene>.png");
  cmd->add_option("--spp", a->spp, "Samples per pixel (overrides render.spp)")->check(CLI::Range(1, 1 << 20));
  cmd->add_option("--threads", a->threads, "Worker threads (default: all cores)")->check(CLI::Range(1, 1024));
  cmd->add_option("--seed", a->seed, "Random seed (overrides render.seed)")->check(CLI::NonNegativeNumber);
  cmd->add_option("--integrator", a->integrator,
                  "whitted | path | albedo | normal | depth | position | id | uv");
  cmd->add_option("--sampler", a->sampler, "center | stratified | random");
  cmd->add_option("--aov", a->aovs,
                  "Extra layers written to EXR (beside a PNG: <output>.exr): albedo,normal,depth,position,id,uv,spp");
  cmd->add_flag("-q,--quiet", a->quiet, "No progress bar or summary");
  cmd->callback([a, &runner] { runner = [a] { return run(*a); }; });
}

}  // namespace anamorph::app
