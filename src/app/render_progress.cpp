// What `anamorph render` says while and after it renders a frame: the progress bar (or an MPI
// log's lines), the summary, the NaN warning.
#include <fmt/format.h>

#include "app/output_guard.h"
#include "app/render_command.h"
#include "scene/scene_schema.h"

namespace anamorph::app {

namespace {

// The frame's bar, its ETA and, in a sequence, the whole job's ETA (frames left at the pace so
// far).
void print_progress(const Progress& p, const std::string& prefix, const JobPlace& job) {
  const int width = 30;
  const int filled = int(p.fraction * width);
  const double mrays = p.seconds > 0 ? p.rays / p.seconds * 1e-6 : 0;
  const double eta = p.fraction > 0 ? p.seconds * (1 - p.fraction) / p.fraction : 0;
  std::string whole;
  if (job.count > 1) {
    const double done = job.index + p.fraction,
                 spent = std::chrono::duration<double>(std::chrono::steady_clock::now() - job.t0)
                             .count();
    whole = done > 0 ? fmt::format(", job {:.0f}s", spent * (job.count - done) / done) : "";
  }
  fmt::print(stderr, "\r{}[{}{}] {:5.1f}%  {:7.2f} Mrays/s  ETA {:.0f}s{}   ", prefix,
             std::string(size_t(filled), '#'), std::string(size_t(width - filled), ' '),
             100 * p.fraction, mrays, eta, whole);
}

}  // namespace

std::function<void(const Progress&)> progress_printer(const RenderSetup& s,
                                                      const std::string& prefix,
                                                      const JobPlace& place, bool bar) {
  // An MPI job's output goes to a log (mpirun forwards it through pipes): a line every 10 s.
  const bool lines = !s.args.quiet && !bar && s.farm;
  if (!bar && !lines) return nullptr;
  auto last =
      std::make_shared<std::chrono::steady_clock::time_point>(std::chrono::steady_clock::now());
  return [last, bar, prefix, place](const Progress& p) {
    const auto now = std::chrono::steady_clock::now();
    if (now - *last < std::chrono::milliseconds(bar ? 100 : 10000) && (!bar || p.fraction < 1))
      return;
    *last = now;
    print_progress(p, prefix, place);
    if (!bar) fmt::print(stderr, "\n");
  };
}

void clear_progress() { fmt::print(stderr, "\r{}\r", std::string(100, ' ')); }

void print_summary(const RenderSetup& s, const std::string& out, const Scene& scene,
                   const RenderStats& st) {
  if (!s.args.quiet) {
    const double per_pixel =
        double(st.samples) / (double(scene.render.width) * scene.render.height);
    // (The scheme by its render.antialias name: lattice or pixel.)
    const std::string sampling = scene.render.adaptive()
                                     ? fmt::format("adaptive ({}), {:.2f} samples/pixel",
                                                   name_of(scene.render.antialias), per_pixel)
                                     : fmt::format("{} spp", scene.render.spp);
    fmt::print(messages(),
               "{}: {}x{}, {}, {} in {:.2f} s, {:.2f} Mrays/s ({:.3f} M rays), {} NaN/Inf samples "
               "dropped\n",
               out, scene.render.width, scene.render.height, sampling,
               name_of(scene.render.integrator), st.seconds, st.mrays_per_second(), st.rays * 1e-6,
               st.nan_samples);
  }
  if (st.nan_samples > 0)
    fmt::print(stderr,
               "warning: {} samples had NaN or Inf radiance and were dropped (first at pixel {},{} "
               "sample {})\n",
               st.nan_samples, st.nan_x, st.nan_y, st.nan_sample);
}

}  // namespace anamorph::app
