#include "server/preview.h"

#ifdef __GLIBC__
#include <malloc.h>
#endif

#include <algorithm>
#include <chrono>

#include "render/denoise_film.h"
#include "render/film.h"
#include "render/frame_output.h"
#include "render/renderer.h"
#include "scene/scene_schema.h"

namespace anamorph::server {

namespace {

using Clock = std::chrono::steady_clock;

// Hands the heap's free pages back to the system when the editor has been idle for a second
// (the preview done, no edit since): what validating edits and rendering previews freed would
// otherwise stay in the process (glibc returns only the top of a heap on its own). A few
// milliseconds, never while the user drags. Under the load test the resting RSS is a fifth
// lower with it (docs/robustness.md).
void release_free_memory() {
#ifdef __GLIBC__
  malloc_trim(0);
#endif
}

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// The settings of one preview render: the scene's, at `w` x `h` with `spp` uniform samples.
RenderSettings preview_settings(const RenderSettings& scene, const PreviewSettings& p, int w, int h,
                                int spp) {
  RenderSettings rs = scene;
  rs.width = w;
  rs.height = h;
  if (p.integrator) select_integrator(rs, *p.integrator);
  rs.antialias = Antialias::Uniform;
  rs.spp = spp;
  rs.time_limit = 0;
  if (spp == 1)
    rs.sampler = SamplerKind::Center;
  else if (rs.sampler == SamplerKind::Center)
    rs.sampler = SamplerKind::Stratified;
  return rs;
}

// The preview as a sink of the render's output: the beauty as 8-bit sRGB RGBA rows gathered into
// a frame, published once complete.
class PreviewSink final : public ImageSink {
 public:
  PreviewSink(std::shared_ptr<PreviewFrame> frame,
              std::function<void(std::shared_ptr<PreviewFrame>)> publish)
      : frame_(std::move(frame)), publish_(std::move(publish)) {}
  // (A member, not a function's static: the preview thread may still render while the process
  // exits, after statics are destroyed; fuzz_api found it.)
  const std::vector<LayerRequest>& requests() const override { return requests_; }
  void prepare(Strip&) const override {}
  void append(const Strip& s) override {
    const std::vector<unsigned char>& px = s.planes[0].u8;
    frame_->rgba.append(px.begin(), px.end());
  }
  void commit() override { publish_(std::move(frame_)); }
  void commit_as(const std::filesystem::path&) override { commit(); }

 private:
  std::vector<LayerRequest> requests_{{"", Encoding::Srgb8}};
  std::shared_ptr<PreviewFrame> frame_;
  std::function<void(std::shared_ptr<PreviewFrame>)> publish_;
};

// Samples per pixel of the refined preview: the scene's own count, or for an adaptive scheme
// (whose count varies) the preview's limit.
int refined_spp(const RenderSettings& rs, const PreviewSettings& p) {
  return std::max(1, std::min(rs.adaptive() ? p.max_spp : rs.spp, p.max_spp));
}

}  // namespace

struct Preview::Job {
  int64_t version = 0;
  std::unique_ptr<Scene> scene;
  bool view_only = false;
  Clock::time_point arrived;
};

void fit_preview(int w, int h, const PreviewSettings& s, int* pw, int* ph) {
  const double k = std::min({1.0, double(s.max_width) / w, double(s.max_height) / h});
  *pw = std::max(1, int(w * k + 0.5));
  *ph = std::max(1, int(h * k + 0.5));
}

Preview::Preview() : thread_([this] { loop(); }) {}

Preview::~Preview() {
  {
    std::lock_guard lock(mu_);
    stop_ = true;
    cancel_ = true;
  }
  cv_.notify_all();
  thread_.join();
}

void Preview::show(int64_t version, std::unique_ptr<Scene> scene, bool view_only) {
  {
    std::lock_guard lock(mu_);
    if (pending_ && !pending_->view_only && view_only) {
      // The geometry change not yet taken up stays; only its view is newer.
      pending_->scene->camera = std::move(scene->camera);
      pending_->scene->render = scene->render;
      pending_->scene->camera_toml = std::move(scene->camera_toml);
      pending_->version = version;
    } else {
      auto job = std::make_shared<Job>();
      job->version = version;
      job->scene = std::move(scene);
      job->view_only = view_only;
      job->arrived = Clock::now();
      pending_ = std::move(job);
    }
    cancel_ = true;
  }
  cv_.notify_all();
}

void Preview::set_settings(const PreviewSettings& s) {
  std::lock_guard lock(mu_);
  settings_ = s;
  cancel_ = true;
  if (!pending_ && scene_) {
    // Render the shown state again under the new settings.
    auto job = std::make_shared<Job>();
    job->version = applied_version_;
    job->view_only = true;
    job->arrived = Clock::now();
    pending_ = std::move(job);
  }
  cv_.notify_all();
}

PreviewSettings Preview::settings() const {
  std::lock_guard lock(mu_);
  return settings_;
}

std::string Preview::error() const {
  std::lock_guard lock(mu_);
  return error_;
}

std::shared_ptr<const PreviewFrame> Preview::wait_frame(uint64_t after, double timeout_s,
                                                        const std::function<bool()>& gone) const {
  const auto deadline = Clock::now() + std::chrono::duration<double>(timeout_s);
  std::unique_lock lock(mu_);
  while (!(frame_ && frame_->seq > after)) {
    if (stop_ || Clock::now() >= deadline || (gone && gone())) return nullptr;
    // Short waits, so that a client that hung up is noticed within 100 ms.
    cv_.wait_for(lock, std::chrono::milliseconds(100));
  }
  return frame_;
}

bool Preview::with_state(int64_t version, double timeout_s,
                         const std::function<void(const Scene&, const Renderer&)>& f) const {
  const auto deadline = Clock::now() + std::chrono::duration<double>(timeout_s);
  {
    std::unique_lock lock(mu_);
    // (version 0, none asked for, still waits for the first state: documents start at 1)
    while (applied_version_ < std::max<int64_t>(version, 1)) {
      if (stop_ || Clock::now() >= deadline) return false;
      cv_.wait_for(lock, std::chrono::milliseconds(20));
    }
  }
  std::lock_guard state(state_mu_);
  if (!scene_ || !renderer_) return false;
  f(*scene_, *renderer_);
  return true;
}

void Preview::publish(std::shared_ptr<PreviewFrame> f) {
  {
    std::lock_guard lock(mu_);
    f->seq = ++seq_;
    frame_ = std::move(f);
  }
  cv_.notify_all();
}

void Preview::loop() {
  bool trimmed = true;  // (nothing freed since the heap was last trimmed)
  for (;;) {
    std::shared_ptr<Job> job;
    {
      std::unique_lock lock(mu_);
      const auto ready = [&] { return stop_ || pending_; };
      if (trimmed) {
        cv_.wait(lock, ready);
      } else if (!cv_.wait_for(lock, std::chrono::seconds(1), ready)) {
        lock.unlock();
        release_free_memory();  // a second without a change: the user is looking
        trimmed = true;
        continue;
      }
      if (stop_) return;
      job = std::move(pending_);
      cancel_ = false;
    }
    trimmed = false;
    try {
      take_up(*job);
    } catch (const std::exception& e) {
      std::lock_guard lock(mu_);
      error_ = e.what();
      continue;
    }
    render_frames(*job);
  }
}

// Makes the job's state the one shown (under state_mu_: with_state may be reading).
void Preview::take_up(Job& job) {
  std::unique_ptr<Renderer> renderer;
  if (job.scene && !job.view_only) renderer = std::make_unique<Renderer>(*job.scene);
  std::lock_guard state(state_mu_);
  if (renderer) {
    renderer_.reset();  // (it refers to the old scene)
    scene_ = std::move(job.scene);
    renderer_ = std::move(renderer);
  } else if (job.scene && scene_) {
    scene_->camera = std::move(job.scene->camera);
    scene_->render = job.scene->render;
    scene_->camera_toml = std::move(job.scene->camera_toml);
    scene_->frame = job.scene->frame;
  }
  std::lock_guard lock(mu_);
  applied_version_ = std::max(applied_version_, job.version);
  error_.clear();
  cv_.notify_all();
}

// The coarse frame, then the refining passes; false when cancelled.
bool Preview::render_frames(const Job& job) {
  if (!scene_ || !renderer_) return false;
  const PreviewSettings ps = settings();
  RenderSettings own;
  {
    std::lock_guard state(state_mu_);
    own = scene_->render;
  }
  int pw = 1, ph = 1;
  fit_preview(own.width, own.height, ps, &pw, &ph);
  const int spp = refined_spp(own, ps);
  struct Step {
    int w, h, spp;
    bool coarse;
  };
  const Step steps[] = {{std::max(1, pw / 4), std::max(1, ph / 4), 1, true}, {pw, ph, spp, false}};
  bool ok = true;
  for (const Step& step : steps) {
    {
      std::lock_guard state(state_mu_);
      scene_->render = preview_settings(own, ps, step.w, step.h, step.spp);
    }
    Film film(step.w, step.h, {});
    RenderOptions opt;
    opt.cancel = &cancel_;
    opt.progressive = !step.coarse;
    std::atomic<int> passes{1};
    opt.on_progress = [&](const Progress& p) { passes = p.passes; };
    opt.on_pass = [&](const Film& f, int pass) {
      if (!cancel_)
        publish_film(job, f, step.coarse ? 0 : pass + 1, step.coarse ? 0 : passes.load(),
                     step.coarse, false);
    };
    const RenderStats st = renderer_->render(film, opt);
    if (st.cancelled || cancel_) {
      ok = false;
      break;
    }
    if (!step.coarse && ps.denoise)
      ok = render_denoised_frame(job, step.w, step.h, step.spp, passes);
  }
  std::lock_guard state(state_mu_);
  scene_->render = own;
  return ok;
}

// The film as the newest frame.
void Preview::publish_film(const Job& job, const Film& f, int pass, int passes, bool coarse,
                           bool denoised) {
  auto frame = std::make_shared<PreviewFrame>();
  frame->version = job.version;
  frame->width = f.width();
  frame->height = f.height();
  frame->coarse = coarse;
  frame->denoised = denoised;
  frame->pass = pass;
  frame->passes = passes;
  frame->seconds = seconds_since(job.arrived);
  std::vector<std::unique_ptr<ImageSink>> sink;
  sink.push_back(std::make_unique<PreviewSink>(
      std::move(frame), [this](std::shared_ptr<PreviewFrame> done) { publish(std::move(done)); }));
  FrameOutput out({f.width(), f.height(), f.grid().size, {}, {}, {}}, std::move(sink));
  out.add_tiles(f);
  out.commit_incomplete();
}

// The settled frame once more, rendered in two halves and denoised, shown as the last pass
// again; nothing when the preview's settings cannot be denoised (1 sample a pixel). False when
// cancelled. (scene_->render holds the settled step's settings.)
bool Preview::render_denoised_frame(const Job& job, int w, int h, int spp, int passes) {
  const RenderSettings rs = scene_->render;
  if (spp < 2 || denoise_unsupported(rs)) return true;
  Film film(w, h, with_denoise_aovs({}));
  RenderOptions opt;
  opt.cancel = &cancel_;
  const DenoisedRender d = render_denoised(*renderer_, rs, film, opt);
  if (!d.denoised || cancel_) return false;
  publish_film(job, film, passes, passes, false, true);
  return true;
}

}  // namespace anamorph::server
