// anamorph._anamorph.Camera: a loaded camera's ray field, rays at given samples, inverse map.
// Arrays are filled by the library's batch generation (camera/ray_field.h) with the GIL released.
#include <fmt/format.h>
#include <tbb/task_arena.h>

#include "bindings.h"
#include "camera/coins.h"
#include "camera/ray_field.h"
#include "camera/source_projection.h"
#include "camera/stmap.h"
#include "camera_handle.h"
#include "math/parallel.h"
#include "render/memory_estimate.h"

namespace anamorph::py {

namespace {

using Doubles = pb::array_t<double, pb::array::c_style | pb::array::forcecast>;

template <class F>
void in_arena(int threads, F&& f) {
  tbb::task_arena arena(arena_concurrency(threads));
  arena.execute(f);
}

// The six ray arrays and the mask for n rays, as numpy arrays of shape lead + (3,) / lead.
struct RayOutput {
  std::vector<double> org, dir, dorg_du, dorg_dv, ddir_du, ddir_dv;
  std::vector<uint8_t> valid;
  explicit RayOutput(size_t n, bool differentials) : org(3 * n), dir(3 * n), valid(n) {
    if (!differentials) return;
    for (auto* v : {&dorg_du, &dorg_dv, &ddir_du, &ddir_dv}) v->resize(3 * n);
  }
  RayArrays arrays() {
    const auto p = [](std::vector<double>& v) { return v.empty() ? nullptr : v.data(); };
    return {p(org), p(dir), p(dorg_du), p(dorg_dv), p(ddir_du), p(ddir_dv), valid.data()};
  }
  pb::dict to_dict(std::vector<pb::ssize_t> lead) && {
    std::vector<pb::ssize_t> vec = lead;
    vec.push_back(3);
    pb::dict d;
    d["org"] = to_array(std::move(org), vec);
    d["dir"] = to_array(std::move(dir), vec);
    if (!dorg_du.empty()) {
      d["dorg_du"] = to_array(std::move(dorg_du), vec);
      d["dorg_dv"] = to_array(std::move(dorg_dv), vec);
      d["ddir_du"] = to_array(std::move(ddir_du), vec);
      d["ddir_dv"] = to_array(std::move(ddir_dv), vec);
    }
    d["valid"] = to_array(std::move(valid), lead).attr("astype")("bool");
    return d;
  }
};

// What RayOutput and its arrays take for n rays, checked before anything is allocated (as a
// render's film is: render/memory_estimate.h).
void check_ray_memory(size_t n, bool differentials) {
  MemoryNeed need;
  need.parts.emplace_back(fmt::format("{} rays x {} B", n, differentials ? 146 : 50),
                          uint64_t(n) * (differentials ? 146 : 50));
  if (const auto shortfall = memory_shortfall(need, "these rays need"))
    raise_memory_error(*shortfall + "; ask for fewer (a smaller width and height)");
}

pb::dict rays(const CameraHandle& c, bool differentials, int threads) {
  check_ray_memory(size_t(c.width()) * size_t(c.height()), differentials);
  RayOutput out(size_t(c.width()) * size_t(c.height()), differentials);
  {
    pb::gil_scoped_release release;
    in_arena(threads, [&] { generate_ray_field(c.camera(), c.width(), c.height(), out.arrays()); });
  }
  return std::move(out).to_dict({c.height(), c.width()});
}

const double* optional_data(const std::optional<Doubles>& a, size_t n, const char* name) {
  if (!a) return nullptr;
  if (size_t(a->size()) != n)
    throw std::invalid_argument(std::string(name) + " must have as many entries as u");
  return a->data();
}

pb::dict generate(const CameraHandle& c, const Doubles& u, const Doubles& v,
                  const std::optional<Doubles>& lens_u, const std::optional<Doubles>& lens_v,
                  const std::optional<Doubles>& time, bool differentials, int threads) {
  const size_t n = size_t(u.size());
  if (size_t(v.size()) != n) throw std::invalid_argument("u and v must have the same size");
  const SampleArrays in{u.data(), v.data(), optional_data(lens_u, n, "lens_u"),
                        optional_data(lens_v, n, "lens_v"), optional_data(time, n, "time")};
  check_ray_memory(n, differentials);
  RayOutput out(n, differentials);
  {
    pb::gil_scoped_release release;
    in_arena(threads, [&] { generate_rays(c.camera(), n, in, out.arrays()); });
  }
  return std::move(out).to_dict({pb::ssize_t(n)});
}

pb::tuple project(const CameraHandle& c, const Doubles& points, int threads) {
  if (points.ndim() != 2 || points.shape(1) != 3)
    throw std::invalid_argument("points must be an (N, 3) array");
  const size_t n = size_t(points.shape(0));
  Projections p;
  {
    pb::gil_scoped_release release;
    in_arena(threads, [&] { p = project_points(c.camera(), n, points.data()); });
  }
  const auto m = pb::ssize_t(p.uv.size() / 2);
  return pb::make_tuple(to_array(std::move(p.uv), {m, 2}),
                        to_array(std::move(p.offsets), {pb::ssize_t(n) + 1}));
}

// The camera's STMap to the source projection `spec` (camera/stmap.h): st (H, W, 2), alpha (H,
// W), direction (H, W, 3), float32; with `inverse` the map the other way at the source's size
// (source_width, source_height; 0: the camera's width and the projection's aspect). A
// non-central camera raises ValueError (NonCentralCamera) unless `depth` > 0 (DepthSphere).
pb::dict stmap(const CameraHandle& c, const std::string& spec, bool inverse, int source_width,
               int source_height, int threads, double depth) {
  const Camera& cam = c.camera();
  const int W = c.width(), H = c.height();
  const bool sized = source_width > 0 && source_height > 0;
  const auto source =
      make_source_projection(spec, sized ? double(source_width) / source_height : 1.0);
  StMap m;
  {
    pb::gil_scoped_release release;
    const std::optional<double> d = depth > 0 ? std::optional(depth) : std::nullopt;
    const DepthSphere sphere = map_sphere(cam, W, H, d);
    in_arena(threads, [&] {
      if (!inverse) {
        m = forward_stmap(cam, *source, W, H, d ? std::optional(sphere) : std::nullopt);
        return;
      }
      const int sw = sized ? source_width : W;
      const int sh = sized ? source_height : std::max(1, int(std::lround(sw / source->aspect())));
      m = inverse_stmap(cam, sphere, *source, sw, sh);
    });
  }
  const pb::ssize_t h = m.height, w = m.width;
  pb::dict d;
  d["st"] = to_array(std::move(m.st), {h, w, 2});
  d["alpha"] = to_array(std::move(m.alpha), {h, w});
  d["direction"] = to_array(std::move(m.direction), {h, w, 3});
  return d;
}

pb::list coins(const CameraHandle& c) {
  pb::list l;
  for (const CoinSite& s : coin_sites(c.camera())) {
    pb::dict d;
    d["coin"] = s.coin;
    d["uv"] = pb::make_tuple(s.uv.x, s.uv.y);
    d["radius"] = s.radius;
    d["strength"] = s.strength;
    d["stiffness"] = s.stiffness;
    l.append(d);
  }
  return l;
}

}  // namespace

void bind_camera(pb::module_& m) {
  pb::class_<CameraHandle>(m, "Camera")
      .def_static("from_text", &CameraHandle::from_text, pb::arg("text"), pb::arg("name"))
      .def_property_readonly("width", &CameraHandle::width)
      .def_property_readonly("height", &CameraHandle::height)
      .def("resized", &CameraHandle::resized, pb::arg("width"), pb::arg("height"))
      .def("describe", [](const CameraHandle& c) { return c.camera().describe(); })
      .def("toml", [](const CameraHandle& c) { return c.scene().camera_toml; })
      .def("warnings", [](const CameraHandle& c) { return c.scene().warnings; })
      .def("coins", &coins)
      .def("rays", &rays, pb::arg("differentials"), pb::arg("threads"))
      .def("generate", &generate, pb::arg("u"), pb::arg("v"), pb::arg("lens_u"), pb::arg("lens_v"),
           pb::arg("time"), pb::arg("differentials"), pb::arg("threads"))
      .def("project", &project, pb::arg("points"), pb::arg("threads"))
      .def("stmap", &stmap, pb::arg("source"), pb::arg("inverse"), pb::arg("source_width"),
           pb::arg("source_height"), pb::arg("threads"), pb::arg("depth") = 0.0);
}

}  // namespace anamorph::py
