// The editor's live preview: one thread renders the newest state of the scene, first at a
// quarter of the preview's size (1 sample per pixel at pixel centers, on screen at once), then at
// the preview's size in progressive passes (1, 1, 2, 4, ... samples per pixel, up to the scene's
// own count or the preview's limit). A new state cancels the render in flight within a packet and
// starts again. The camera is the scene's own, built for the image's true size: the preview shows
// exactly what the final render will, smaller (a fisheye's circle, a coin's magnification).
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "scene/scene.h"

namespace anamorph {
class Film;
class Renderer;
}  // namespace anamorph

namespace anamorph::server {

struct PreviewFrame {
  uint64_t seq = 0;     // counts frames published
  int64_t version = 0;  // the document version shown
  int width = 0, height = 0;
  int pass = 0, passes = 0;  // pass 0 is the coarse one; the last pass of passes is the final
  bool coarse = false;
  bool denoised = false;  // the settled frame denoised (PreviewSettings::denoise)
  double seconds = 0;     // from the state's arrival to this frame
  std::string rgba;       // width * height * 4 bytes, 8-bit sRGB, straight alpha
};

struct PreviewSettings {
  int max_width = 960, max_height = 540;  // the preview fits in this box, keeping the aspect
  std::optional<std::string> integrator;  // an integrator or a view; none: the scene's own
  int max_spp = 16;
  // Once the progressive passes have settled, the frame rendered again in two halves and
  // denoised (render/denoise_film.h) and shown as one more frame, when the preview's settings
  // allow it (at least 2 samples a pixel).
  bool denoise = false;
};

// The preview size for an image of w x h in the settings' box (never larger than the image).
void fit_preview(int w, int h, const PreviewSettings& s, int* pw, int* ph);

class Preview {
 public:
  Preview();
  ~Preview();
  Preview(const Preview&) = delete;
  Preview& operator=(const Preview&) = delete;

  // A new state to show: a whole scene (the geometry changed), or with `view_only` a scene loaded
  // with load_view whose camera and settings replace the shown scene's. Cancels what is
  // rendering.
  void show(int64_t version, std::unique_ptr<Scene> scene, bool view_only);
  void set_settings(const PreviewSettings& s);
  PreviewSettings settings() const;

  // The newest frame after `after` (by seq), waiting up to `timeout_s` while `gone` says the
  // client is still there; null when none came.
  std::shared_ptr<const PreviewFrame> wait_frame(uint64_t after, double timeout_s,
                                                 const std::function<bool()>& gone) const;

  // Runs `f(scene, renderer)` on the state of document version >= `version` once the preview
  // thread has taken it up (waits up to `timeout_s`; false when it did not come). The scene and
  // renderer do not change while f runs.
  bool with_state(int64_t version, double timeout_s,
                  const std::function<void(const Scene&, const Renderer&)>& f) const;
  // The last state that failed to build (an Embree error, say), or "".
  std::string error() const;

 private:
  struct Job;
  void loop();
  void take_up(Job& job);
  bool render_frames(const Job& job);
  bool render_denoised_frame(const Job& job, int w, int h, int spp, int passes);
  void publish_film(const Job& job, const Film& f, int pass, int passes, bool coarse,
                    bool denoised);
  void publish(std::shared_ptr<PreviewFrame> f);

  mutable std::mutex mu_;  // everything below but the render itself
  mutable std::condition_variable cv_;
  std::shared_ptr<Job> pending_;
  PreviewSettings settings_;
  bool stop_ = false;
  std::atomic<bool> cancel_{false};
  std::shared_ptr<const PreviewFrame> frame_;
  uint64_t seq_ = 0;
  std::string error_;
  // The state shown: changed only by the preview thread, under state_mu_ (with_state reads it).
  mutable std::mutex state_mu_;
  std::unique_ptr<Scene> scene_;
  std::unique_ptr<Renderer> renderer_;
  int64_t applied_version_ = 0;
  std::thread thread_;
};

}  // namespace anamorph::server
