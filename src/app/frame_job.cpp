#include "app/frame_job.h"

#include <fmt/format.h>

#include <algorithm>
#include <functional>

#include "app/build_id.h"
#include "app/common.h"
#include "render/denoise_film.h"
#include "render/frame_output.h"

namespace anamorph::app {

namespace fs = std::filesystem;

namespace {

constexpr const char* kPartial = ".partial";

[[noreturn]] void damaged(const fs::path& file, const std::string& why) {
  throw CheckpointError(fmt::format("checkpoint '{}' is damaged: {}", file.string(), why));
}

// A checkpoint of another render is refused, naming what differs.
std::unique_ptr<CheckpointReader> open_checkpoint(const FrameJob& job,
                                                  const CheckpointIdentity& id) {
  if (job.checkpoint.empty() || !fs::exists(job.checkpoint)) return nullptr;
  auto reader = std::make_unique<CheckpointReader>(job.checkpoint);
  const std::string diff = identity_changes(reader->identity(), id);
  const auto build = [](const CheckpointIdentity& i) {
    const auto b =
        std::find_if(i.begin(), i.end(), [](const auto& e) { return e.first == "build"; });
    return b == i.end() ? std::string() : b->second;
  };
  if (build(reader->identity()) != build(id))
    throw CheckpointError(fmt::format(
        "checkpoint '{}' was made by another build of anamorph (build {}, this one is {}), whose "
        "pixels may differ: finish it with that build, or delete it to start over",
        job.checkpoint.string(),
        build(reader->identity()).empty() ? "not recorded" : build(reader->identity()), build(id)));
  if (!diff.empty())
    throw CheckpointError(
        fmt::format("checkpoint '{}' belongs to another render: {} (delete it to start over)",
                    job.checkpoint.string(), diff));
  return reader;
}

FrameOutputSpec output_spec(const FrameJob& job) {
  const RenderSettings& rs = job.scene.render;
  return {rs.width, rs.height, rs.tile_size, job.aovs, job.files, job.metadata};
}

RenderOptions render_options(const FrameJob& job) {
  RenderOptions opt;
  opt.threads = job.threads;
  opt.aovs = job.aovs;
  opt.cancel = job.cancel ? job.cancel : &interrupt_flag();
  opt.on_progress = job.on_progress;
  opt.tile_times = job.tile_times;
  opt.farm = job.farm;
  opt.progressive = false;
  return opt;
}

// The files in place; any image so far of an earlier attempt is out of date, and so is the
// checkpoint unless a time limit stopped the render (then it continues the render).
void finish(const FrameJob& job, FrameOutput& out, std::unique_ptr<CheckpointWriter> ck,
            bool time_limited) {
  if (time_limited)
    out.commit_incomplete();
  else
    out.commit();
  ck.reset();
  std::error_code ec;
  if (!job.checkpoint.empty() && !time_limited) fs::remove(job.checkpoint, ec);
  for (const fs::path& p : job.files) fs::remove(FrameOutput::with_suffix(p, kPartial), ec);
}

// The checkpoint written from here on: a new one, or the one read continued after `append_at`.
std::unique_ptr<CheckpointWriter> open_writer(const FrameJob& job, const CheckpointIdentity& id,
                                              uint64_t append_at) {
  if (job.checkpoint.empty()) return nullptr;
  return std::make_unique<CheckpointWriter>(job.checkpoint, id, job.checkpoint_every, append_at);
}

// The frame's end. Interrupted: the image so far as NAME.partial.EXT. Otherwise the files, and
// when a time limit stopped the render, `reached()` says how far it got.
void conclude(const FrameJob& job, FrameOutput& out, std::unique_ptr<CheckpointWriter> ck,
              FrameResult& r, const std::function<std::string()>& reached) {
  if (r.stats.cancelled) {
    out.commit_partial(kPartial);
    r.interrupted = true;
    return;
  }
  r.time_limited = r.stats.time_limited;
  if (r.time_limited) r.reached = reached();
  finish(job, out, std::move(ck), r.time_limited);
}

// Uniform and lattice sampling: every tile complete, straight into the files and the checkpoint.
FrameResult render_streamed(const FrameJob& job, const CheckpointIdentity& id) {
  FrameResult r;
  auto reader = open_checkpoint(job, id);
  FrameOutput out(output_spec(job));
  std::vector<uint8_t> skip(out.grid().count(), 0);
  if (reader) {
    reader->read({[&](ResolvedTile&& t) {
                    if (t.index >= skip.size() || skip[t.index])
                      damaged(job.checkpoint, "a tile twice");
                    if (!fits(t, out.plan(), out.grid().rect(t.index), job.aovs))
                      damaged(job.checkpoint, "a tile of the wrong size");
                    skip[t.index] = 1;
                    ++r.resumed_tiles;
                    out.add(std::move(t));
                  },
                  nullptr, nullptr});
    r.resumed = true;
  }
  std::unique_ptr<CheckpointWriter> ck = open_writer(job, id, reader ? reader->end() : 0);
  reader.reset();
  r.stats = job.renderer.render_resolved(out.grid(), render_options(job), skip, out.plan(),
                                         [&](ResolvedTile&& rt) {
                                           if (ck) ck->add_tile(rt);
                                           out.add(std::move(rt));
                                         });
  conclude(job, out, std::move(ck), r,
           [&] { return fmt::format("{} of {} tiles", out.tiles_added(), out.grid().count()); });
  return r;
}

// A pass render's checkpoint into `film`: each tile's sums and the pass it finished, the pass
// to continue and its active pixels. Whether it held a pass start (without one, nothing is used).
bool read_passes(const FrameJob& job, CheckpointReader& reader, Film& film,
                 std::vector<int>& tile_pass, PassResume& resume, FrameResult& r) {
  const RenderSettings& rs = job.scene.render;
  const size_t tiles = film.grid().count(), nf = aov_floats(job.aovs);
  bool have_pass = false;
  reader.read({nullptr,
               [&](PassTile&& t) {
                 if (t.index >= tiles) damaged(job.checkpoint, "a tile outside the image");
                 TileBuffer& b = film.tile(t.index);
                 if (t.sums.size() != b.sums().size() || t.aov.size() != b.sums().size() * nf)
                   damaged(job.checkpoint, "a tile of the wrong size");
                 b.sums() = std::move(t.sums);
                 b.aov_sums() = std::move(t.aov);
                 if (tile_pass[t.index] < 0) ++r.resumed_tiles;
                 tile_pass[t.index] = t.pass;
               },
               [&](int pass, std::vector<uint8_t>&& active) {
                 const size_t pixels = size_t(rs.width) * size_t(rs.height);
                 if (active.size() != (Renderer::streams(rs) ? 0 : pixels) || pass < 0)
                   damaged(job.checkpoint, "a pass record of the wrong size");
                 resume.pass = pass;
                 resume.active = std::move(active);
                 have_pass = true;
               }});
  r.resumed = have_pass;
  // (The reader refuses pass tiles without their pass start; none are used without one.)
  if (!have_pass) std::fill(tile_pass.begin(), tile_pass.end(), -1), r.resumed_tiles = 0;
  return have_pass;
}

// Per-pixel adaptive sampling (the stopping rule looks across tiles) and time-limited uniform
// sampling: a film in passes. The checkpoint is rewritten at each pass start (every tile's sums and
// the pass's active pixels) and gets each tile's sums as it finishes the pass.
FrameResult render_passes(const FrameJob& job, const CheckpointIdentity& id) {
  FrameResult r;
  const RenderSettings& rs = job.scene.render;
  Film film(rs.width, rs.height, job.aovs, rs.tile_size);
  const size_t tiles = film.grid().count();
  std::vector<int> tile_pass(tiles, -1);
  PassResume resume;
  bool have_pass = false;
  auto reader = open_checkpoint(job, id);
  if (reader) have_pass = read_passes(job, *reader, film, tile_pass, resume, r);
  std::unique_ptr<CheckpointWriter> ck = open_writer(job, id, have_pass ? reader->end() : 0);
  reader.reset();
  resume.tile_pass = tile_pass;
  RenderOptions opt = render_options(job);
  opt.progressive = true;
  if (have_pass) opt.resume = &resume;
  opt.on_pass_start = [&](int pass, const std::vector<uint8_t>& active) {
    if (!ck) return;
    // The log anew, replacing the old one only once complete with its pass start.
    ck->begin_rewrite();
    for (size_t i = 0; i < tiles; ++i)
      if (const TileBuffer* t = film.tile_if_any(i); t && tile_pass[i] >= 0)
        ck->add_pass_tile(tile_pass[i], i, *t);
    ck->add_pass_start(pass, active);
    ck->commit_rewrite();
  };
  opt.on_tile_pass = [&](size_t i, int pass, const TileBuffer& tile) {
    tile_pass[i] = pass;
    if (ck) ck->add_pass_tile(pass, i, tile);
  };
  r.stats = job.renderer.render(film, opt);
  FrameOutput out(output_spec(job));
  out.add_tiles(film);
  conclude(job, out, std::move(ck), r, [&] {
    const int pass = r.stats.pass;
    const auto done =
        size_t(std::count_if(tile_pass.begin(), tile_pass.end(), [&](int p) { return p >= pass; }));
    return done == 0 ? fmt::format("{} of {} passes", pass, r.stats.passes)
                     : fmt::format("pass {} of {} in {} of {} tiles", pass + 1, r.stats.passes,
                                   done, tiles);
  });
  return r;
}

// Denoised: the two halves in a film (with the denoiser's layers; the outputs take the job's),
// the beauty denoised, then the files. No checkpoint (setup_render refuses one).
FrameResult render_denoised_frame(const FrameJob& job) {
  FrameResult r;
  const RenderSettings& rs = job.scene.render;
  Film film(rs.width, rs.height, with_denoise_aovs(job.aovs), rs.tile_size);
  const DenoisedRender d = render_denoised(job.renderer, rs, film, render_options(job));
  r.stats = d.stats;
  r.denoise_seconds = d.denoise_seconds;
  FrameOutput out(output_spec(job));
  out.add_tiles(film);
  // (Cancelled while denoising: the image so far is the undenoised frame.)
  if (d.denoise.cancelled) r.stats.cancelled = true;
  conclude(job, out, nullptr, r, [] { return std::string("the first half of the samples"); });
  return r;
}

}  // namespace

bool renders_in_passes(const RenderSettings& rs) {
  return !Renderer::streams(rs) || (rs.time_limit > 0 && !rs.adaptive());
}

CheckpointIdentity frame_identity(const FrameJob& job) {
  CheckpointIdentity id = {{"anamorph", ANAMORPH_VERSION}};
  if (!job.checkpoint.empty()) id.emplace_back("build", build_id());
  for (const fs::path& f : job.files) id.emplace_back("output." + sink_kind(f).name, f.string());
  id.emplace_back("frame", fmt::format("{}", job.scene.frame));
  std::string aovs;
  for (Aov a : job.aovs) aovs += std::string(aovs.empty() ? "" : ",") + aov_info(a).name;
  id.emplace_back("aovs", aovs);
  id.emplace_back("layers", describe_plan(output_plan(job.files, job.aovs)));
  for (auto& e : flatten_toml(job.scene.effective_toml)) id.push_back(std::move(e));
  std::string args;
  for (const std::string& a : command_args()) args += a + '\0';
  id.emplace_back("command", args);
  return id;
}

FrameResult render_to_files(const FrameJob& job) {
  if (job.denoise) return render_denoised_frame(job);
  const CheckpointIdentity id = frame_identity(job);
  return renders_in_passes(job.scene.render) ? render_passes(job, id) : render_streamed(job, id);
}

std::map<std::string, std::string> frame_metadata(const Scene& scene, double frame,
                                                  const std::vector<Aov>& aovs) {
  std::map<std::string, std::string> metadata;
  metadata["anamorph.version"] = ANAMORPH_VERSION;
  metadata["anamorph.command"] = command_line();
  metadata["anamorph.scene"] = scene.path;
  metadata["anamorph.camera"] = scene.camera->describe() + "\n" + scene.camera_toml;
  if (!scene.animated.empty()) metadata["anamorph.frame"] = fmt::format("{}", frame);
  for (Aov a : aovs)
    metadata[std::string("anamorph.layer.") + aov_info(a).name] = aov_info(a).definition;
  return metadata;
}

}  // namespace anamorph::app
