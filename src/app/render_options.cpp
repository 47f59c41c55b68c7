// `anamorph render`'s options: declared on the command, and what they come to (RenderSetup).
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <cstdlib>
#include <memory>

#include "app/output_guard.h"
#include "app/render_command.h"
#include "app/thread_option.h"
#include "io/image_sink.h"
#include "render/coin_layer.h"
#include "render/frame_output.h"

namespace anamorph::app {

namespace {

// "90", "90s", "5m", "2h" as seconds; false if malformed.
bool parse_duration(const std::string& text, double* seconds) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || !(v > 0) || v > 1e7) return false;
  const std::string unit = end;
  const double scale = unit.empty() || unit == "s" ? 1 : unit == "m" ? 60 : unit == "h" ? 3600 : 0;
  *seconds = v * scale;
  return scale > 0;
}

// The options that override scene keys, as keys.
std::vector<std::string> scene_keys(const RenderArgs& a) {
  std::vector<std::string> extra;
  if (a.spp) extra.push_back(fmt::format("render.spp={}", *a.spp));
  if (a.seed) extra.push_back(fmt::format("render.seed={}", *a.seed));
  if (a.integrator) extra.push_back(fmt::format("render.integrator=\"{}\"", *a.integrator));
  if (a.sampler) extra.push_back(fmt::format("render.sampler=\"{}\"", *a.sampler));
  return extra;
}

// --aov's sampled layers; "coins" is drawn from the camera after rendering, not sampled: it sets
// `coins` instead. Throws std::invalid_argument for an unknown name.
std::vector<Aov> sampled_aovs(const std::string& aovs, bool* coins) {
  std::string list;
  for (size_t s = 0; s <= aovs.size() && !aovs.empty();) {
    size_t e = aovs.find(',', s);
    if (e == std::string::npos) e = aovs.size();
    const std::string name = aovs.substr(s, e - s);
    if (name == "coins")
      *coins = true;
    else
      list += (list.empty() ? "" : ",") + name;
    s = e + 1;
  }
  return parse_aovs(list);
}

// The checks of options that need no scene; kOk or kBadInput (the error printed).
int check_options(RenderSetup& s) {
  if (!parse_duration(s.args.checkpoint_every, &s.checkpoint_every)) {
    print_error(fmt::format("--checkpoint-every {}: expected seconds, e.g. 60, 60s, 5m or 1h",
                            s.args.checkpoint_every));
    return kBadInput;
  }
  if (s.args.scene.scene.empty()) {
    fmt::print(stderr, "error: render needs a scene file (or --resume CHECKPOINT)\n");
    return kBadInput;
  }
  if (s.args.denoise && (!s.args.checkpoint.empty() || s.args.coins_overlay)) {
    print_error(
        fmt::format("--denoise cannot be combined with {}: the denoiser needs the two "
                    "half buffers of the whole frame, which {} does not keep",
                    s.args.coins_overlay ? "--aov coins" : "--checkpoint",
                    s.args.coins_overlay ? "the coin overlay" : "a checkpoint"));
    return kBadInput;
  }
  if (!find_sink_kind(s.out)) {
    print_error(fmt::format("-o {}: {}", s.out, unsupported_extension(s.out)));
    return kBadInput;
  }
  return kOk;
}

}  // namespace

int setup_render(const RenderArgs& a, RenderSetup* s) {
  s->args = a;
  s->extra = scene_keys(a);
  try {
    s->aovs = sampled_aovs(a.aovs, &s->args.coins_overlay);
  } catch (const std::invalid_argument& e) {
    print_error(fmt::format("--aov: {}", e.what()));
    return kBadInput;
  }
  s->out = a.output.empty() ? default_render_output(a.scene.scene, !a.frames.empty()) : a.output;
  // What the outputs are checked against (app/output_guard.h): before loading the scene file,
  // after it every file the load read.
  std::vector<LayerSpec> layers = render_layers(s->aovs);
  if (s->args.coins_overlay) layers.push_back(coins_layer_spec());
  s->outs = {s->out,       a.output.empty(), layers,  s->args.coins_overlay,
             a.checkpoint, a.stats,          a.video, ""};
  s->scene_file = scene_file_input(a.scene.scene);
  if (const int rc = check_options(*s); rc != kOk) return rc;
  if (is_standard_output(s->out)) messages_to_stderr();  // (`-o /dev/stdout`: the image alone)
  return kOk;
}

void add_render(CLI::App& app, std::function<int()>& runner) {
  auto a = std::make_shared<RenderArgs>();
  CLI::App* cmd = app.add_subcommand("render", "Render a scene to an image (PNG or EXR)");
  a->scene.add_to(*cmd, false);
  cmd->add_option(
      "-o,--output", a->output,
      "Output image (.png or .exr); default out/<scene name>.png (out/<scene name>_%04d.png "
      "with --frames). With --frames, a pattern such as out/frame_%04d.png");
  cmd->add_option("--spp", a->spp,
                  "Samples per pixel (overrides render.spp; implies uniform sampling)")
      ->check(CLI::Range(1, 1 << 20));
  cmd->add_option("--threads", a->threads, "Worker threads (default: all cores)")
      ->check(thread_count_check());
  cmd->add_option("--seed", a->seed, "Random seed (overrides render.seed)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--integrator", a->integrator,
                  "whitted | path, or a view: albedo | normal | depth | position | id | uv");
  cmd->add_option("--sampler", a->sampler, "center | stratified | random");
  cmd->add_option("--aov", a->aovs,
                  "Extra layers written to EXR (beside a PNG: <output>.exr): "
                  "albedo,normal,depth,distance,depth_z,position,position_camera,id,uv,spp,"
                  "flow_forward,flow_backward,motion,coins "
                  "(coins also writes <output>.coins.png with the markers drawn in)");
  cmd->add_option("--frames", a->frames,
                  "Render frames FIRST:LAST of the scene's [[animate]] keys (inclusive)");
  cmd->add_option("--video", a->video,
                  "After --frames, assemble the frames into this video with ffmpeg");
  cmd->add_option("--fps", a->fps, "Frames per second of --video (default 30)")
      ->check(CLI::Range(1, 1000));
  cmd->add_flag("-q,--quiet", a->quiet, "No progress bar or summary");
  cmd->add_option("--checkpoint", a->checkpoint,
                  "Keep a checkpoint here while rendering (with --frames, a pattern such as "
                  "ckpt/frame_%04d.ckpt); an existing one of the same render is resumed");
  cmd->add_option("--stats", a->stats,
                  "Write every tile's cost (time, samples, rays) as JSON, for planning cluster "
                  "renders (a frame pattern with --frames, e.g. stats_%04d.json)");
  cmd->add_option("--checkpoint-every", a->checkpoint_every,
                  "How often the checkpoint is forced to disk: 60s (default), 5m, 1h");
  cmd->add_option("--resume", a->resume,
                  std::string("Continue the render a checkpoint belongs to (the same command, "
                              "resumed); only ") +
                      kWithResume + " may be given with it");
  cmd->add_flag("--denoise", a->denoise,
                "Denoise the beauty (NFOR on two half buffers, guided by albedo, normal and "
                "depth, rendered for it; docs/denoise.md); needs uniform sampling");
  cmd->add_flag("--skip-existing", a->skip_existing,
                "Skip frames whose output file is already there (complete: files appear only "
                "when done)");
  cmd->callback([a, cmd, &runner] {
    if (!a->resume.empty()) a->with_resume = resume_options(*cmd);
    runner = [a] { return run_render(*a); };
  });
}

}  // namespace anamorph::app
