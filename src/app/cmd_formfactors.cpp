// `anamorph formfactors`: form factors between the scene's objects measured with a hemispherical
// virtual camera, and optionally the radiosity solution checked against the path tracer.
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <filesystem>
#include <stdexcept>

#include "accel/accel.h"
#include "app/common.h"
#include "app/form_factor_output.h"
#include "app/output_guard.h"
#include "io/image_io.h"
#include "math/user_text.h"
#include "render/form_factors.h"
#include "render/radiosity.h"

namespace anamorph::app {

namespace {

struct FormFactorArgs {
  SceneOptions scene;
  std::vector<std::string> objects, inward;
  int samples = 2048, rays = 256, depth = 64;
  uint64_t seed = 0;
  std::string output;
  bool radiosity = false;
};

// SIGINT or SIGTERM stopped the measurement (app/interrupt.h).
int interrupted(const FormFactorArgs& a) {
  fmt::print(stderr, "interrupted: the form factors were not finished{}\n",
             a.output.empty() ? "" : "; " + a.output + " not written");
  return kInterrupted;
}

int run(const FormFactorArgs& a) {
  const std::vector<std::pair<std::filesystem::path, std::string>> outputs{
      {a.output, "-o " + a.output}};
  if (!a.output.empty()) check_outputs(scene_file_input(a.scene.scene), outputs);
  const Scene s = load(a.scene);
  if (!a.output.empty()) check_outputs(s.inputs, outputs);
  const Accel accel(s);
  FormFactorOptions o;
  o.origins = a.samples, o.rays = a.rays, o.seed = a.seed;
  o.sources = a.objects, o.inward = a.inward;
  o.cancel = &interrupt_flag();
  FormFactors f;
  std::vector<Color> B;
  try {
    // What radiosity needs is checked before minutes of measuring.
    if (a.radiosity) check_radiosity_inputs(s, accel, a.inward);
    RenderPhase phase;
    f = measure_form_factors(accel, o);
    if (interrupt_flag()) return interrupted(a);
    if (a.radiosity) B = solve_radiosity(s, accel, f);
  } catch (const std::invalid_argument& e) {
    print_error(e.what());
    return kBadInput;
  }
  for (const std::string& note : f.notes) print_warning(note);
  check_finite(f, a.radiosity ? &B : nullptr);
  print_table(f);
  if (a.radiosity) {
    PathRadiance p;
    {
      RenderPhase phase;
      p = path_traced_radiance(s, accel, f, o, a.depth);
      if (interrupt_flag()) return interrupted(a);
    }
    check_finite(f, &B, &p);
    print_radiosity(f, B, p);
  }
  if (!a.output.empty()) {
    const std::string ext = std::filesystem::path(a.output).extension().string();
    const std::string text = ext == ".json" ? to_json(f, a.radiosity ? &B : nullptr) : to_csv(f);
    write_file_atomic(a.output, text.data(), text.size());
    fmt::print("wrote {}\n", printable(a.output));
  }
  return kOk;
}

}  // namespace

void add_formfactors(CLI::App& app, std::function<int()>& runner) {
  auto a = std::make_shared<FormFactorArgs>();
  CLI::App* cmd = app.add_subcommand(
      "formfactors",
      "Form factors between the scene's objects, measured by a hemispherical virtual camera "
      "(equal projected solid angle per pixel) at points spread over each object");
  a->scene.add_to(*cmd);
  cmd->add_option("--objects", a->objects, "Objects whose rows to measure (default: all)")
      ->delimiter(',');
  cmd->add_option("--inward", a->inward,
                  "Objects whose surfaces face inward (enclosures: a room box, a dome)")
      ->delimiter(',');
  cmd->add_option("--samples", a->samples, "Points per object, stratified by area")
      ->check(CLI::Range(1, kMaxFormFactorOrigins));
  cmd->add_option("--rays", a->rays, "Hemisphere camera samples per point")
      ->check(CLI::Range(1, kMaxFormFactorRays));
  cmd->add_option("--seed", a->seed, "Random seed");
  cmd->add_option("-o,--output", a->output,
                  "Write the matrix: .csv (long form, RFC 4180 quoting) or .json")
      ->check([](const std::string& p) {
        const std::string e = std::filesystem::path(p).extension().string();
        return e == ".csv" || e == ".json" ? std::string() : "use .csv or .json";
      });
  cmd->add_flag("--radiosity", a->radiosity,
                "Solve (I - rho F) B = E and check B / pi against the path tracer's mean "
                "radiance per object");
  cmd->add_option("--depth", a->depth, "Path tracer depth for the --radiosity check")
      ->check(CLI::Range(1, kMaxFormFactorPathDepth));
  cmd->callback([a, &runner] { runner = [a] { return run(*a); }; });
}

}  // namespace anamorph::app
