// `anamorph formfactors`: form factors between the scene's objects measured with a hemispherical
// virtual camera, and optionally the radiosity solution checked against the path tracer.
#include <fmt/format.h>

#include <filesystem>
#include <stdexcept>

#include "accel/accel.h"
#include "app/common.h"
#include "io/image_io.h"
#include "render/form_factors.h"

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

std::string json_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) < 0x20) {
      out += fmt::format("\\u{:04x}", int(c));
      continue;
    }
    out += c;
  }
  return out + "\"";
}

std::string to_csv(const FormFactors& f) {
  std::string s = "from,to,area_from,F,stderr\n";
  for (size_t r = 0; r < f.rows.size(); ++r)
    for (size_t c = 0; c <= f.names.size(); ++c)
      s += fmt::format("{},{},{:.10g},{:.10g},{:.3g}\n", f.names[size_t(f.rows[r])],
                       c < f.names.size() ? f.names[c] : "environment", f.areas[size_t(f.rows[r])],
                       f.F[r][c], f.error[r][c]);
  return s;
}

std::string to_json(const FormFactors& f, const std::vector<Color>* B) {
  std::string s = "{\n  \"objects\": [";
  for (size_t i = 0; i < f.names.size(); ++i)
    s += fmt::format("{}{{\"name\": {}, \"area\": {:.10g}}}", i ? ", " : "",
                     json_string(f.names[i]), f.areas[i]);
  s += "],\n  \"columns\": [";
  for (size_t i = 0; i <= f.names.size(); ++i)
    s += (i ? ", " : "") + json_string(i < f.names.size() ? f.names[i] : "environment");
  const auto matrix = [&](const std::vector<std::vector<double>>& m, const char* fmtspec) {
    std::string t = "[";
    for (size_t r = 0; r < m.size(); ++r) {
      t += r ? ",\n    [" : "\n    [";
      for (size_t c = 0; c < m[r].size(); ++c)
        t += (c ? ", " : "") + fmt::format(fmt::runtime(fmtspec), m[r][c]);
      t += "]";
    }
    return t + "]";
  };
  s += "],\n  \"rows\": [";
  for (size_t r = 0; r < f.rows.size(); ++r)
    s += (r ? ", " : "") + json_string(f.names[size_t(f.rows[r])]);
  s += "],\n  \"F\": " + matrix(f.F, "{:.10g}") + ",\n  \"stderr\": " + matrix(f.error, "{:.3g}");
  s += fmt::format(",\n  \"reciprocity_worst_z\": {:.4g}", f.worst_reciprocity_z);
  if (B) {
    s += ",\n  \"radiosity\": [";
    for (size_t i = 0; i < B->size(); ++i)
      s += fmt::format("{}[{:.10g}, {:.10g}, {:.10g}]", i ? ", " : "", (*B)[i].x, (*B)[i].y,
                       (*B)[i].z);
    s += "]";
  }
  return s + "\n}\n";
}

void print_table(const FormFactors& f) {
  fmt::print(
      "form factors F(from -> to) +- standard error ({} objects, environment = nothing hit)\n",
      f.names.size());
  for (size_t r = 0; r < f.rows.size(); ++r) {
    const size_t i = size_t(f.rows[r]);
    double sum = 0;
    fmt::print("  {} (area {:.6g})\n", f.names[i], f.areas[i]);
    for (size_t c = 0; c <= f.names.size(); ++c) {
      sum += f.F[r][c];
      if (f.F[r][c] > 0)
        fmt::print("    -> {:<24} {:.6f} +- {:.6f}\n",
                   c < f.names.size() ? f.names[c] : "environment", f.F[r][c], f.error[r][c]);
    }
    fmt::print("    row sum {:.6f}\n", sum);
  }
  if (f.worst_i >= 0)
    fmt::print("reciprocity A_i F_ij = A_j F_ji: worst {} / {} differ by {:.2f} standard errors\n",
               f.names[size_t(f.worst_i)], f.names[size_t(f.worst_j)], f.worst_reciprocity_z);
}

int run(const FormFactorArgs& a) {
  const Scene s = load(a.scene);
  const Accel accel(s);
  FormFactorOptions o;
  o.origins = a.samples, o.rays = a.rays, o.seed = a.seed;
  o.sources = a.objects, o.inward = a.inward;
  o.cancel = &interrupt_flag();
  FormFactors f;
  std::vector<Color> B;
  try {
    RenderPhase phase;
    f = measure_form_factors(accel, o);
    if (interrupt_flag()) return kFailure;
    if (a.radiosity) B = solve_radiosity(s, accel, f);
  } catch (const std::invalid_argument& e) {
    print_error(fmt::format("{}", e.what()));
    return kBadInput;
  }
  print_table(f);
  if (a.radiosity) {
    PathRadiance p;
    {
      RenderPhase phase;
      p = path_traced_radiance(s, accel, f, o, a.depth);
      if (interrupt_flag()) return kFailure;
    }
    fmt::print("radiosity (I - rho F) B = E; mean radiance B / pi against the path tracer's\n");
    for (size_t i = 0; i < B.size(); ++i) {
      const Color L = B[i] / kPi;
      double z = 0;
      for (int c = 0; c < 3; ++c)
        if (p.error[i][c] > 0) z = std::max(z, std::abs(L[c] - p.mean[i][c]) / p.error[i][c]);
      fmt::print(
          "  {:<24} B/pi ({:.5f}, {:.5f}, {:.5f})  path ({:.5f}, {:.5f}, {:.5f}) +- "
          "{:.5f}  ({:.1f} standard errors)\n",
          f.names[i], L.x, L.y, L.z, p.mean[i].x, p.mean[i].y, p.mean[i].z,
          std::max({p.error[i].x, p.error[i].y, p.error[i].z}), z);
    }
  }
  if (!a.output.empty()) {
    const std::string ext = std::filesystem::path(a.output).extension().string();
    const std::string text = ext == ".json" ? to_json(f, a.radiosity ? &B : nullptr) : to_csv(f);
    write_file_atomic(a.output, text.data(), text.size());
    fmt::print("wrote {}\n", a.output);
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
  cmd->add_option("-o,--output", a->output, "Write the matrix: .csv (long form) or .json")
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
