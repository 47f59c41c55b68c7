// `anamorph info`: what a scene loaded.
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include "accel/accel.h"
#include "app/common.h"
#include "camera/coins.h"
#include "scene/scene_schema.h"

namespace anamorph::app {

namespace {

int run(const SceneOptions& o) {
  const Scene s = load(o);
  const Accel accel(s);
  fmt::print("scene       {}\n", s.path);
  const std::string sampling =
      s.render.adaptive() ? fmt::format("adaptive antialiasing ({})", name_of(s.render.antialias))
                          : fmt::format("{} spp ({})", s.render.spp, name_of(s.render.sampler));
  fmt::print("image       {}x{}, {}, integrator {}, max_depth {}\n", s.render.width,
             s.render.height, sampling, s.render.shown(), s.render.max_depth);
  fmt::print("camera      {}\n", s.camera->describe());
  const auto sites = coin_sites(*s.camera);
  if (!sites.empty()) {
    fmt::print("coins       {} image position(s)\n", sites.size());
    for (const CoinSite& c : sites)
      fmt::print(
          "  coin[{}]   (uc, vc) = ({:.4f}, {:.4f}) = pixel ({:.1f}, {:.1f}), radius {:.3g}, "
          "strength {:.3g}\n",
          c.coin, c.uv.x, c.uv.y, c.uv.x * s.render.width, c.uv.y * s.render.height, c.radius,
          c.strength);
  }
  fmt::print("triangles   {} unique, {} after instancing\n", accel.stats().unique_triangles,
             accel.stats().instanced_triangles);
  fmt::print("meshes      {} prototypes, {} placements ({} as Embree instances)\n",
             s.prototypes.size(), s.instances.size(), accel.stats().instances);
  fmt::print("shapes      {}\n", s.shapes.size());
  for (const auto& sh : s.shapes) fmt::print("  {:<12} {}\n", name_of(sh.kind), sh.name);
  fmt::print("materials   {}\n", s.materials.size());
  for (const auto& m : s.materials)
    fmt::print("  {:<24} {}{}\n", m->name, m->describe(), m->is_emissive() ? ", emissive" : "");
  fmt::print("lights      {}\n", s.lights.size());
  for (const auto& l : s.lights) fmt::print("  {:<12} {}\n", name_of(l.kind), l.name);
  fmt::print("environment {}\n", s.environment.image
                                     ? "image"
                                     : (s.environment.present() ? "constant colour" : "none"));
  const Bounds3 b = accel.bounds();
  if (b.empty())
    fmt::print("bounds      empty\n");
  else
    fmt::print("bounds      [{:.4g}, {:.4g}, {:.4g}] .. [{:.4g}, {:.4g}, {:.4g}]\n", b.lo.x, b.lo.y,
               b.lo.z, b.hi.x, b.hi.y, b.hi.z);
  for (const std::string& line : s.model_summaries) fmt::print("model       {}\n", line);
  // What no output of a run may overwrite (app/output_guard.h).
  fmt::print("reads       {} file(s)\n", s.inputs.size());
  for (const FileRead& f : s.inputs) fmt::print("  {}: {}\n", f.role, f.path.string());
  return kOk;
}

}  // namespace

void add_info(CLI::App& app, std::function<int()>& runner) {
  auto o = std::make_shared<SceneOptions>();
  CLI::App* cmd = app.add_subcommand(
      "info", "Print what a scene loads: objects, triangles, materials, lights, camera");
  o->add_to(*cmd);
  cmd->callback([o, &runner] { runner = [o] { return run(*o); }; });
}

}  // namespace anamorph::app
