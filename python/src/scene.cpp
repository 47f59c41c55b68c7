// anamorph._anamorph.Scene: a loaded scene, what it holds, and renders into numpy arrays. A render
// runs on a worker thread while the calling thread, holding the GIL only briefly, reports progress
// and watches for KeyboardInterrupt (Ctrl-C), which cancels the render at its next packet.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <future>
#include <limits>
#include <mutex>
#include <thread>

#include "accel/accel.h"
#include "bindings.h"
#include "camera/coins.h"
#include "camera_handle.h"
#include "math/parallel.h"
#include "render/coin_layer.h"
#include "render/denoise_film.h"
#include "render/form_factors.h"
#include "render/memory_estimate.h"
#include "render/radiosity.h"
#include "render/renderer.h"
#include "render/tile_buffer.h"
#include "scene/scene_loader.h"
#include "scene/scene_pose.h"
#include "scene/scene_schema.h"

namespace anamorph::py {

namespace {

struct RenderRequest {
  std::vector<std::string> overrides;  // image size, spp, seed, integrator, sampler
  std::vector<std::string> aovs;       // names; "coins" is drawn, not sampled
  int threads = 0;
  pb::object progress;   // callable(dict) or None
  bool denoise = false;  // the CLI's --denoise (render/denoise_film.h)
};

pb::dict progress_dict(const Progress& p) {
  pb::dict d;
  d["fraction"] = p.fraction;
  d["seconds"] = p.seconds;
  d["rays"] = p.rays;
  d["pass"] = p.pass;
  d["passes"] = p.passes;
  return d;
}

pb::dict stats_dict(const RenderStats& s) {
  pb::dict d;
  d["seconds"] = s.seconds;
  d["rays"] = s.rays;
  d["samples"] = s.samples;
  d["nan_samples"] = s.nan_samples;
  return d;
}

// An OutputImage's layers as (H, W, C) float32 arrays: "rgba" for the beauty, AOVs by name.
pb::dict layers_dict(OutputImage&& img) {
  pb::dict d;
  for (ImageLayer& l : img.layers) {
    const std::vector<pb::ssize_t> shape = {img.height, img.width, pb::ssize_t(l.channels.size())};
    d[pb::str(l.name.empty() ? "rgba" : l.name)] = to_array(std::move(l.data), shape);
  }
  return d;
}

// The CLI's memory check (render/memory_estimate.h) before a render allocates anything: a frame
// the machine cannot hold raises MemoryError saying what it needs (was: 7.8 GB allocated before
// Python's MemoryError, for 65536 x 65536).
void check_render_memory(const Scene& s, const std::vector<Aov>& aovs, int threads, bool denoise) {
  RenderShape shape;
  shape.width = s.render.width;
  shape.height = s.render.height;
  shape.tile_size = s.render.tile_size;
  shape.threads = threads > 0 ? threads : int(std::thread::hardware_concurrency());
  shape.aov_floats = aov_floats(aovs);
  shape.whole_film = true;  // (the frame comes back whole, as arrays)
  shape.active_mask = !Renderer::streams(s.render);
  shape.output_image = true;
  shape.denoise = denoise;
  if (const auto shortfall = memory_shortfall(estimate_render_memory(s, shape)))
    raise_memory_error(*shortfall + "; lower the width and height or the AOVs");
}

class SceneHandle {
 public:
  explicit SceneHandle(SceneSource s)
      : source_(std::move(s)),
        scene_(std::make_shared<Scene>(source_.load())),
        loaded_places_(scene_->placed_objects) {}

  const Scene& scene() const { return *scene_; }
  CameraHandle camera() const { return CameraHandle(source_, view({}), scene_); }
  pb::dict info();
  pb::dict render(const RenderRequest& req);
  pb::dict form_factors(const FormFactorOptions& o, bool radiosity, int depth);
  pb::dict last_stats() const { return stats_dict(stats_); }

 private:
  // The camera and settings with `extra` overrides, the geometry shared with scene_.
  std::shared_ptr<const Scene> view(const std::vector<std::string>& extra) const {
    return std::make_shared<const Scene>(source_.load_view(extra, *scene_));
  }
  RenderStats run(Film& film, const RenderOptions& opt, const pb::object& progress,
                  bool denoise = false);
  // Frames + 1 / - 1 attached to scene_ for one render (flow, motion), and taken off after.
  struct OtherFrames {
    Scene& scene;
    OtherFrames(const SceneHandle& h, const std::vector<Aov>& aovs,
                const std::vector<std::string>& extra)
        : scene(*h.scene_) {
      scene.next = aovs_need_frame(aovs, 1) ? h.other_frame(1, extra) : nullptr;
      scene.previous = aovs_need_frame(aovs, -1) ? h.other_frame(-1, extra) : nullptr;
    }
    ~OtherFrames() { scene.next = scene.previous = nullptr; }
    OtherFrames(const OtherFrames&) = delete;
    OtherFrames& operator=(const OtherFrames&) = delete;
  };
  // The scene at this frame + step (only the view when nothing else animates).
  std::shared_ptr<const FrameMotion> other_frame(int step,
                                                 const std::vector<std::string>& extra) const {
    SceneSource s = source_;
    s.frame += step;
    if (animates_view_only(*scene_)) return frame_motion(s.load_view(extra, *scene_), scene_.get());
    return frame_motion(s.load(extra));
  }
  // Moves the mesh objects to `want` (a view's object.N.transform overrides, or the places
  // loaded) and the acceleration structure with them (Renderer::repose: no load).
  void place(const std::vector<PlacedObject>& want) {
    if (!place_objects(*scene_, want) || !renderer_) return;
    pb::gil_scoped_release release;
    renderer_->repose();
  }
  // Takes the render lock (without the GIL, so a render on another thread can finish) and
  // builds the acceleration structure on first use.
  std::unique_lock<std::mutex> lock_and_build() {
    // A progress callback that renders (or asks for info) would wait for itself.
    if (render_thread_ == std::this_thread::get_id())
      throw std::runtime_error("a scene cannot be used from its own render's progress callback");
    pb::gil_scoped_release release;
    std::unique_lock<std::mutex> lock(render_mutex_);
    if (!renderer_) renderer_ = std::make_unique<Renderer>(*scene_);
    return lock;
  }

  SceneSource source_;
  std::shared_ptr<Scene> scene_;
  std::vector<PlacedObject> loaded_places_;  // the mesh objects' transforms in the file
  std::unique_ptr<Renderer> renderer_;
  std::mutex render_mutex_;  // one render at a time (a render swaps the view into scene_)
  std::atomic<std::thread::id> render_thread_{};  // the thread inside run(), if any
  RenderStats stats_;
};

// Swaps a view's camera and settings into the scene for one render, and back.
struct ViewSwap {
  Scene& scene;
  Scene& view;
  ViewSwap(Scene& s, Scene& v) : scene(s), view(v) { swap(); }
  ~ViewSwap() { swap(); }
  void swap() {
    std::swap(scene.render, view.render);
    std::swap(scene.camera, view.camera);
  }
};

pb::dict SceneHandle::render(const RenderRequest& req) {
  arena_concurrency(req.threads);  // (the CLI's check of --threads: a ValueError, up front)
  std::vector<Aov> aovs;
  bool coins = false;
  std::string list;
  for (const std::string& a : req.aovs) {
    if (a == "coins")
      coins = true;
    else
      list += (list.empty() ? "" : ",") + a;
  }
  aovs = parse_aovs(list);
  const auto lock = lock_and_build();
  Scene view = req.overrides.empty() ? Scene() : source_.load_view(req.overrides, *scene_);
  // Objects the overrides place move for this render (and stay until one places them else).
  place(view.placed_objects.empty() ? loaded_places_ : view.placed_objects);
  // Flow and motion layers look at frames + 1 and - 1: loaded beside this one for this render,
  // with the same overrides, as `anamorph render` does.
  const OtherFrames others(*this, aovs, req.overrides);
  std::optional<ViewSwap> swap;
  if (!req.overrides.empty()) swap.emplace(*scene_, view);
  if (req.denoise)
    if (const auto why = denoise_unsupported(scene_->render))
      throw pb::value_error("denoise: " + *why);
  const std::vector<Aov> film_aovs = req.denoise ? with_denoise_aovs(aovs) : aovs;
  check_render_memory(*scene_, film_aovs, req.threads, req.denoise);
  Film film(scene_->render.width, scene_->render.height, film_aovs);
  RenderOptions opt;
  opt.threads = req.threads;
  opt.aovs = film_aovs;
  stats_ = run(film, opt, req.progress, req.denoise);
  OutputImage img = film.output();
  img.layers.resize(1 + aovs.size());  // (the denoiser's own layers come after the asked ones)
  if (coins) img.layers.push_back(coins_layer(*scene_));
  return layers_dict(std::move(img));
}

RenderStats SceneHandle::run(Film& film, const RenderOptions& options, const pb::object& progress,
                             bool denoise) {
  std::atomic<bool> cancel{false};
  std::mutex progress_mutex;
  std::optional<Progress> latest;
  RenderOptions opt = options;
  opt.cancel = &cancel;
  opt.on_progress = [&](const Progress& p) {
    const std::lock_guard<std::mutex> l(progress_mutex);
    latest = p;
  };
  const Renderer& r = *renderer_;
  struct Inside {  // marks this thread as rendering, for lock_and_build's check
    std::atomic<std::thread::id>& id;
    explicit Inside(std::atomic<std::thread::id>& i) : id(i) { id = std::this_thread::get_id(); }
    ~Inside() { id = std::thread::id(); }
  } inside(render_thread_);
  auto done = std::async(std::launch::async, [&] {
    return denoise ? render_denoised(r, scene_->render, film, opt).stats : r.render(film, opt);
  });
  // Progress and Ctrl-C are handled here, on the calling thread, every 50 ms.
  const auto report = [&] {
    std::optional<Progress> p;
    {
      const std::lock_guard<std::mutex> l(progress_mutex);
      p.swap(latest);
    }
    if (p && !progress.is_none()) progress(progress_dict(*p));
  };
  try {
    for (;;) {
      std::future_status st;
      {
        pb::gil_scoped_release release;
        st = done.wait_for(std::chrono::milliseconds(50));
      }
      if (PyErr_CheckSignals() != 0) throw pb::error_already_set();
      report();
      if (st == std::future_status::ready) break;
    }
  } catch (...) {
    cancel = true;
    pb::gil_scoped_release release;
    done.wait();
    throw;
  }
  return done.get();
}

pb::dict SceneHandle::info() {
  const auto lock = lock_and_build();
  const Scene& s = *scene_;
  const Accel& accel = renderer_->accel();
  pb::dict d;
  d["path"] = s.path;
  d["width"] = s.render.width;
  d["height"] = s.render.height;
  d["integrator"] = std::string(s.render.shown());
  d["antialias"] = std::string(name_of(s.render.antialias));
  d["spp"] = s.render.spp;
  d["sampler"] = std::string(name_of(s.render.sampler));
  d["camera"] = s.camera->describe();
  d["unique_triangles"] = accel.stats().unique_triangles;
  d["instanced_triangles"] = accel.stats().instanced_triangles;
  pb::list shapes, materials, lights;
  for (const auto& sh : s.shapes)
    shapes.append(
        pb::dict(pb::arg("type") = std::string(name_of(sh.kind)), pb::arg("name") = sh.name));
  for (const auto& m : s.materials) materials.append(m->name);
  for (const auto& l : s.lights)
    lights.append(
        pb::dict(pb::arg("type") = std::string(name_of(l.kind)), pb::arg("name") = l.name));
  d["shapes"] = shapes;
  d["materials"] = materials;
  d["lights"] = lights;
  d["meshes"] = s.instances.size();
  // The name of each object id (what the `id` layer holds): a mesh part's instance (a glTF
  // node's name) or a shape's name.
  pb::list objects;
  for (uint32_t id = 0; id < accel.object_count(); ++id) {
    const Accel::Record& r = accel.record(id);
    objects.append(r.kind == Accel::Record::Kind::Shape ? s.shapes[r.source].name
                                                        : s.instances[r.source].name);
  }
  d["objects"] = objects;
  const Bounds3 b = accel.bounds();
  d["bounds"] = b.empty() ? pb::object(pb::none())
                          : pb::object(pb::make_tuple(pb::make_tuple(b.lo.x, b.lo.y, b.lo.z),
                                                      pb::make_tuple(b.hi.x, b.hi.y, b.hi.z)));
  d["animated"] = s.animated;
  d["frames"] = pb::make_tuple(s.first_key, s.last_key);
  d["warnings"] = s.warnings;
  return d;
}

// Rows x columns as a float64 (rows, cols) array.
pb::array_t<double> matrix(const std::vector<std::vector<double>>& m) {
  std::vector<double> flat;
  for (const auto& row : m) flat.insert(flat.end(), row.begin(), row.end());
  const pb::ssize_t rows = pb::ssize_t(m.size()), cols = m.empty() ? 0 : pb::ssize_t(m[0].size());
  return to_array(std::move(flat), {rows, cols});
}

pb::array_t<double> colors(const std::vector<Color>& c) {
  std::vector<double> flat;
  for (const Color& x : c) flat.insert(flat.end(), {x.x, x.y, x.z});
  return to_array(std::move(flat), {pb::ssize_t(c.size()), 3});
}

pb::dict SceneHandle::form_factors(const FormFactorOptions& o, bool radiosity, int depth) {
  const auto lock = lock_and_build();
  FormFactors f;
  std::vector<Color> B;
  PathRadiance path;
  {
    pb::gil_scoped_release release;
    if (radiosity) check_radiosity_inputs(*scene_, renderer_->accel(), o.inward);
    f = measure_form_factors(renderer_->accel(), o);
    if (radiosity) {
      B = solve_radiosity(*scene_, renderer_->accel(), f);
      path = path_traced_radiance(*scene_, renderer_->accel(), f, o, depth);
    }
  }
  pb::dict d;
  d["objects"] = f.names;
  std::vector<std::string> columns = f.names, rows;
  columns.emplace_back(kEnvironmentColumn);
  for (int r : f.rows) rows.push_back(f.names[size_t(r)]);
  d["columns"] = columns;
  d["rows"] = rows;
  d["areas"] = to_array(std::vector<double>(f.areas), {pb::ssize_t(f.areas.size())});
  d["F"] = matrix(f.F);
  d["stderr"] = matrix(f.error);
  d["reciprocity_worst_z"] = f.worst_reciprocity_z;
  pb::dict unmeasured;
  for (size_t i = 0; i < f.no_row.size(); ++i)
    if (!f.no_row[i].empty()) unmeasured[pb::str(f.names[i])] = f.no_row[i];
  d["unmeasured"] = unmeasured;
  d["notes"] = f.notes;
  if (radiosity) {
    d["radiosity"] = colors(B);
    d["path_radiance"] = colors(path.mean);
    d["path_radiance_stderr"] = colors(path.error);
  }
  return d;
}

SceneSource source_of(std::string path, std::string text, std::vector<std::string> overrides,
                      double frame) {
  SceneSource s;
  s.path = std::move(path);
  s.text = std::move(text);
  s.name = s.path.empty() ? "<string>" : s.path;
  s.overrides = std::move(overrides);
  s.frame = frame;
  return s;
}

}  // namespace

void bind_scene(pb::module_& m) {
  pb::dict limits;
  limits["samples"] = pb::make_tuple(1, kMaxFormFactorOrigins);
  limits["rays"] = pb::make_tuple(1, kMaxFormFactorRays);
  limits["depth"] = pb::make_tuple(1, kMaxFormFactorPathDepth);
  limits["seed"] = pb::make_tuple(0, std::numeric_limits<uint64_t>::max());
  m.attr("FORM_FACTOR_LIMITS") = limits;
  pb::class_<SceneHandle>(m, "Scene")
      .def(pb::init([](const std::string& path, std::vector<std::string> overrides, double frame) {
             return std::make_unique<SceneHandle>(source_of(path, "", std::move(overrides), frame));
           }),
           pb::arg("path"), pb::arg("overrides"), pb::arg("frame"))
      .def_static(
          "from_text",
          [](const std::string& text, std::vector<std::string> overrides, double frame) {
            return std::make_unique<SceneHandle>(source_of("", text, std::move(overrides), frame));
          },
          pb::arg("text"), pb::arg("overrides"), pb::arg("frame"))
      .def("info", &SceneHandle::info)
      .def(
          "form_factors",
          [](SceneHandle& s, int samples, int rays, std::vector<std::string> objects,
             std::vector<std::string> inward, uint64_t seed, bool radiosity, int depth) {
            if (samples < 1 || rays < 1 || depth < 1)
              throw pb::value_error("samples, rays and depth must be at least 1");
            FormFactorOptions o;
            o.origins = samples, o.rays = rays, o.seed = seed;
            o.sources = std::move(objects), o.inward = std::move(inward);
            return s.form_factors(o, radiosity, depth);
          },
          pb::arg("samples"), pb::arg("rays"), pb::arg("objects"), pb::arg("inward"),
          pb::arg("seed"), pb::arg("radiosity"), pb::arg("depth"))
      .def("camera", &SceneHandle::camera)
      .def("warnings", [](const SceneHandle& s) { return s.scene().warnings; })
      .def("last_stats", &SceneHandle::last_stats)
      .def(
          "render",
          [](SceneHandle& s, std::vector<std::string> overrides, std::vector<std::string> aovs,
             int threads, pb::object progress, bool denoise) {
            return s.render(
                {std::move(overrides), std::move(aovs), threads, std::move(progress), denoise});
          },
          pb::arg("overrides"), pb::arg("aovs"), pb::arg("threads"), pb::arg("progress"),
          pb::arg("denoise") = false);
}

}  // namespace anamorph::py
