// Everything a render needs, after parsing and loading, before acceleration structures.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "camera/virtual_camera.h"
#include "io/read_log.h"
#include "material/material.h"
#include "model/mesh.h"
#include "scene/light.h"
#include "scene/loaders.h"
#include "scene/shape.h"

namespace anamorph {

// What a pixel shows instead of radiance: one AOV. Chosen by `integrator = "albedo"` and so on,
// but not an integrator (docs/scene-format.md, "Views"); Beauty: the integrator's radiance.
enum class View { Beauty, Albedo, Normal, Depth, Position, Id, Uv };
// The closed sets of [render], in the order of their names in scene_schema (sampler_names()
// and so on): an enum's value is its name's index there.
enum class SamplerKind { Center, Stratified, Random };
enum class PixelFilter { Box, Gaussian };
// Resolved at load: the file's "adaptive" means Lattice for whitted, Pixel for the others.
enum class Antialias { Uniform, Lattice, Pixel };

struct RenderSettings {
  int width = 640, height = 480;
  // The light transport, by name: one of declared_integrators() (scene_schema.h), made by
  // render/'s registry. Set both through select_integrator().
  std::string integrator = "whitted";
  View view = View::Beauty;
  int spp = 1;
  SamplerKind sampler = SamplerKind::Stratified;
  int max_depth = 5;
  // Whitted: a reflected or refracted ray is traced only while the product of the coefficients
  // that lead to it is at least this (POV-Ray's adc_bailout, 1/255 by default).
  double bailout = 1.0 / 255;
  uint64_t seed = 0;
  PixelFilter filter = PixelFilter::Box;
  double filter_radius = 1.5;  // gaussian: radius in pixels (box: pixel area)
  int tile_size = 32;
  // Antialiasing, resolved at load to one of: "uniform" (spp samples per pixel); "lattice" (the
  // paper's contrast-driven corner subdivision seeded by the camera's distortion, whitted only);
  // "pixel" (per-pixel progressive sampling between min_spp and max_spp that stops each pixel
  // once its estimated error is small). The scene file's "adaptive" means lattice for whitted,
  // pixel for the other integrators.
  Antialias antialias = Antialias::Lattice;
  double aa_threshold = 0.1;      // contrast that splits a square (lattice)
  int aa_depth = 3;               // maximum subdivision levels per pixel (lattice)
  bool aa_distortion = true;      // stretched pixels start subdivided (lattice)
  int min_spp = 8;                // pixel: first pass (whitted's default is 2)
  int max_spp = 1024;             // pixel
  double noise_threshold = 0.01;  // pixel: estimated relative error that stops a pixel
  double time_limit = 0;          // pixel: seconds, 0 = none (breaks determinism)

  // Whether the samples per pixel vary: an adaptive scheme with a radiance integrator (the AOV
  // integrators take `spp` samples under any scheme).
  bool adaptive() const { return antialias != Antialias::Uniform && view == View::Beauty; }
  // Whether a pixel's samples differ only by where they fall in it (Whitted's radiance, not a
  // view): lattice antialiasing by default, two first samples, and its own stopping rule.
  bool deterministic() const;
  // What a pixel shows: the view's name, or the integrator's (`anamorph info`, logs).
  std::string_view shown() const;
};

// A glTF model's rig placed in the scene (scene/scene_pose.h poses it at a frame): which of
// the scene's instances, prototypes, cameras and lights its model's lists start at.
struct SceneRig {
  std::shared_ptr<const GltfRig> rig;
  Transform world_from_model;  // the object's transform
  uint32_t first_instance = 0, first_prototype = 0;
  int first_camera = -1, first_light = -1;  // -1: the object dropped them
  bool animate = true;                      // false: the file's static pose, always
};

// A mesh [[object]] as loaded: its table's index under `object`, its `transform`, and its
// instances (Scene::instances from first_instance on) within its model, so that it can be moved
// without loading it again (place_objects, scene_pose.h). A view read by load_view with
// `object.N.transform` overrides holds only `table` and `transform` of each mesh object.
struct PlacedObject {
  int table = 0;
  Transform transform;
  uint32_t first_instance = 0;
  std::vector<Transform> model_from_object;
  int rig = -1;               // its Scene::rigs entry, or -1
  bool moves_others = false;  // it brought lights or cameras (placed once, at the load)
};

struct Scene;

// The scene at another frame, as motion vectors need it: that frame's camera and the transforms
// of its instances and analytic shapes, indexed as the scene's own (frame_motion), and its
// geometry there for the occlusion test (null: the objects do not move, the scene's own holds).
struct FrameMotion {
  double frame = 0;
  std::shared_ptr<const VirtualCamera> camera;
  std::vector<Transform> instances, shapes;
  std::shared_ptr<const Scene> geometry;
};

struct Scene {
  std::string path;  // the scene file
  RenderSettings render;
  std::unique_ptr<VirtualCamera> camera;
  std::string camera_toml;  // the [camera] table as written (for metadata)
  // The whole scene as rendered: includes merged, animation evaluated at `frame`, overrides
  // applied (checkpoints compare it to refuse resuming a changed scene).
  std::string effective_toml;

  MaterialList materials;
  std::vector<Prototype> prototypes;
  std::vector<Instance> instances;
  std::vector<AnalyticShape> shapes;
  std::vector<Light> lights;
  Environment environment;
  std::vector<std::string> warnings;
  std::vector<std::string> model_summaries;  // each model's LoadedModel::summary, for `info`
  double frame = 0;                          // the animation frame this scene was built for
  std::vector<std::string> animated;         // keys with [[animate]] entries
  double first_key = 0, last_key = 0;        // frame range covered by the keys
  std::vector<ModelCamera> model_cameras;    // cameras found in loaded models (`gltf_camera`)
  std::vector<SceneRig> rigs;                // glTF models' animation
  std::vector<PlacedObject> placed_objects;  // the mesh objects, by table order
  double fps = 24;                           // [animation] fps: glTF time = frame / fps
  // Object motion blur (scene/scene_pose.h): the camera's shutter [open, close] in frames
  // relative to `frame`, and [animation] motion_steps, the times the animation is posed at.
  double shutter_open = 0, shutter_close = 0;
  int motion_steps = 3;
  // Every file the load read (scene, includes, textures, models and their buffers, ray tables),
  // with its role: no output of the run may overwrite one (app/output_guard.h).
  std::vector<FileRead> inputs;
  // The scene at frame + 1 and frame - 1, when a render asks for forward or backward flow (the
  // flow_forward, flow_backward AOVs); null otherwise.
  std::shared_ptr<const FrameMotion> next, previous;

  size_t triangle_count() const;  // unique (prototype) triangles
  size_t instanced_triangle_count() const;
};

// `other`, the same scene file loaded at another frame, as a FrameMotion: its camera, and the
// transforms of the instances and shapes of `geometry` (default: `other` itself; a view loaded
// alone by load_view has none, and shares the geometry of the scene it was loaded with).
std::shared_ptr<const FrameMotion> frame_motion(Scene&& other, const Scene* geometry = nullptr);

}  // namespace anamorph
