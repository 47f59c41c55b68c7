// What one render call shares between its tiles: the settings read once, the integrator, and how
// a camera sample whose first hit is known becomes radiance and AOV values. Internal to the
// renderer (renderer.cpp, tile_sampler.cpp).
#pragma once

#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "accel/accel.h"
#include "camera/camera.h"
#include "render/integrator.h"
#include "render/tile_buffer.h"
#include "scene/scene.h"

namespace anamorph {

// One camera sample's outcome.
struct SampleResult {
  Color L;
  double alpha = 0;  // 0: no ray
  AovSample aov;
};

// Whether a sample's radiance can enter the film: finite, and within single precision (the film's
// sums are floats: beyond 3.4e38 it would be stored as inf). Other samples are dropped and
// counted as NaN/Inf samples, with the first one's pixel.
inline bool film_storable(const Color& L) {
  constexpr double kMax = std::numeric_limits<float>::max();
  return std::abs(L.x) <= kMax && std::abs(L.y) <= kMax && std::abs(L.z) <= kMax;
}

// What a render's beauty shows: radiance, or one AOV (RenderSettings::view).
enum class RenderMode { Radiance, Albedo, Normal, Depth, Position, Id, Uv };

struct RenderJob {
  // `settings`: the scene's render settings, or a render's own (RenderOptions::settings).
  RenderJob(const Scene& scene, const Accel& accel, const RenderContext& ctx,
            const RenderSettings& settings, int width, int height,
            const std::vector<Aov>& film_aovs);

  const Scene& scene;
  const Accel& accel;
  const RenderSettings& rs;
  RenderMode mode;
  std::unique_ptr<Integrator> integrator;
  bool want_aovs;               // AOV values: for the film's layers or a view
  bool film_aovs;               // the film has AOV layers
  Transform camera_from_world;  // the camera rig at shutter open, inverted (depth_z)
  // Flow toward another frame: its camera (null: none), per object id the map taking this
  // frame's point to that frame's (none: the object is not there), and that frame's geometry to
  // test whether the moved point is hidden there (this frame's when the objects do not move).
  struct FlowTarget {
    bool wanted = false;     // the film has this flow layer or the motion layer
    bool occlusion = false;  // the flow layer: hidden points have none
    const Camera* camera = nullptr;
    std::vector<std::optional<Transform>> there_from_here;
    // Per object id of a deforming mesh (a glTF skin or animated morph targets): its prototype
    // and mesh (-1: the hit's), followed by its vertices instead of its transform.
    struct Deforming {
      uint32_t prototype = 0, instance = 0;
      int mesh = -1;
    };
    std::vector<std::optional<Deforming>> deforming;
    const Accel* accel = nullptr;
    std::shared_ptr<const Scene> scene;  // keeps `own` valid
    std::shared_ptr<const Accel> own;    // built for the other frame's geometry
  };
  FlowTarget flow[2];  // forward (frame + 1), backward (frame - 1)
  // Whether primary hits need their surface geometry (points, normals, uv): not for depth, ids
  // or albedo without textures when there are no AOV layers.
  bool hit_surface;
  int W, H;
  double du, dv;  // one pixel, in image units (ray differentials)
  // Uniform sampling: each sample's share of a pixel, as a footprint scale (1/sqrt(spp)).
  double uniform_scale;
  std::vector<uint8_t> textured;  // per material: some texture is not a constant
  // Per material: a hit on it needs the pixel's footprint (a texture filters over it, or rays go
  // on from it and carry it along; Whitted's rays go on only from mirrors and glass).
  std::vector<uint8_t> needs_footprint;
  const std::atomic<bool>* cancel;

  bool cancelled() const { return cancel && cancel->load(std::memory_order_relaxed); }

  // The share of a pixel one of n samples stands for, as a footprint scale (never below 1/8
  // pixel: finer footprints only add texture noise).
  static double footprint_scale(uint32_t n);

  // Completes a camera sample at image position `uv` whose first hit is known. `footprint` is the
  // sample's share of a pixel as a scale of the pixel's footprint; `cam_ray()` gives the camera ray
  // with its differentials (asked for only where a footprint is needed: primary packets hold their
  // rays as arrays). Writes into `out` (reused by the caller: building a fresh result per sample
  // meant zeroing ~150 bytes per ray, a visible cost for primary-ray renders).
  template <class CamRay>
  void finish(const Ray& ray, const CamRay& cam_ray, const Hit* hit, Vec2 uv, Rng& rng,
              uint64_t& rays, SampleResult& out, double footprint = 1) const {
    out.alpha = 1;
    out.aov.hit = false;
    Footprint fp;
    // Footprints only matter where something is filtered: textures, or rays that go on (their
    // ray cones carry it to textures further along).
    if (hit && needs_footprint[hit->material])
      fp = footprint_at(cam_ray(), du * footprint, dv * footprint, *hit);
    if (want_aovs && hit) fill_aovs(ray, *hit, uv, fp, out.aov);
    out.L = mode == RenderMode::Radiance ? integrator->radiance(ray, hit, fp, rng, rays)
                                         : aov_beauty(out.aov);
  }

  // The camera sample at image position uv: lens and time drawn from rng when the camera uses them.
  CameraSample camera_sample(Vec2 uv, Rng& rng) const;
  // A camera sample's time in the shutter, as its ray carries it to moving objects (0 when none
  // moves).
  double ray_time(const CameraSample& cs) const;
  // One full camera sample at image position uv (single ray; adaptive subdivision, tests).
  SampleResult sample_at(Vec2 uv, Rng& rng, uint64_t& rays, double footprint = 1) const;
  // kCameraBatch lattice points of adaptive sampling as sample_at gives them (each lane's random
  // numbers from its key, its footprint as given), the camera rays generated as a batch and
  // traced as one packet.
  void lattice_samples(const Vec2* uv, const uint64_t* keys, const double* footprints,
                       const bool* use, SampleResult* out, uint64_t& rays,
                       CameraRayBatch* keep) const;

 private:
  void fill_aovs(const Ray& ray, const Hit& hit, Vec2 uv, const Footprint& fp, AovSample& a) const;
  // The layers a view never shows: depth conventions, camera-space position, flow.
  FlowTarget flow_target(const FrameMotion* other, bool occlusion) const;
  void fill_vision_aovs(const Hit& hit, Vec2 uv, AovSample& a) const;
  // The flow of the point `hit` sees from image position uv toward `to`, in pixels (of several
  // images, the nearest): false when it has no image there; *hidden when `to` tests occlusion
  // and another surface hides it there.
  bool flow_at(const FlowTarget& to, const Hit& hit, Vec2 uv, Vec2* flow, bool* hidden) const;
  // The deforming meshes' object ids of `to` (to.scene: the other frame's geometry).
  void find_deforming(FlowTarget& to) const;
  // Whether prototype `proto` has the same meshes and triangles in `other` (vertices may move).
  bool same_triangles(uint32_t proto, const Scene& other) const;
  // Where the point `hit` sees is at the other frame: moved with its object, or on a deforming
  // mesh the same barycentric combination of its triangle's vertices there; none when its
  // object is not there.
  std::optional<Vec3> moved_point(const FlowTarget& to, const Hit& hit) const;
  // Whether the point q, seen at image position at by `to`'s camera, is hidden there.
  static bool hidden(const FlowTarget& to, const Vec3& q, Vec2 at);
  Color aov_beauty(const AovSample& a) const;
};

}  // namespace anamorph
