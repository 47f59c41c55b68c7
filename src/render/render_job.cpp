#include "render/render_job.h"

#include <algorithm>
#include <cmath>

#include "render/shading.h"
#include "scene/gltf_rig.h"

namespace anamorph {

namespace {

RenderMode mode_of(View view) {
  switch (view) {
    case View::Albedo:
      return RenderMode::Albedo;
    case View::Normal:
      return RenderMode::Normal;
    case View::Depth:
      return RenderMode::Depth;
    case View::Position:
      return RenderMode::Position;
    case View::Id:
      return RenderMode::Id;
    case View::Uv:
      return RenderMode::Uv;
    case View::Beauty:
      break;
  }
  return RenderMode::Radiance;
}

// A stable, well-spread colour for an object id.
Color id_color(double id) {
  const uint64_t h = mix64(uint64_t(id + 1));
  return {double(h & 0xff) / 255, double((h >> 8) & 0xff) / 255, double((h >> 16) & 0xff) / 255};
}

}  // namespace

RenderJob::RenderJob(const Scene& s, const Accel& a, const RenderContext& ctx,
                     const RenderSettings& settings, int width, int height,
                     const std::vector<Aov>& aovs)
    : scene(s),
      accel(a),
      rs(settings),
      mode(mode_of(rs.view)),
      integrator(mode == RenderMode::Radiance ? make_integrator(rs.integrator, ctx) : nullptr),
      want_aovs(!aovs.empty() || mode != RenderMode::Radiance),
      film_aovs(!aovs.empty()),
      camera_from_world(s.camera->rig().inverse()),
      W(width),
      H(height),
      cancel(ctx.cancel) {
  // A sample filters textures over its share of the pixel: 1/sqrt(spp) of it with uniform
  // sampling; adaptive subdivision passes the lattice spacing each sample stands for, and
  // per-pixel adaptive sampling the share given by the samples the pixel has once the pass ends.
  uniform_scale = footprint_scale(uint32_t(rs.spp));
  du = 1.0 / W;
  dv = 1.0 / H;
  for (const auto& m : s.materials) textured.push_back(m->textured());
  for (size_t i = 0; i < s.materials.size(); ++i) {
    const Material& m = *s.materials[i];
    needs_footprint.push_back(textured[i] ||
                              (mode == RenderMode::Radiance && integrator->continues_from(m)));
  }
  const bool any_texture = std::find(textured.begin(), textured.end(), 1) != textured.end();
  hit_surface = film_aovs || !(mode == RenderMode::Depth || mode == RenderMode::Id ||
                               (mode == RenderMode::Albedo && !any_texture));
  const auto has = [&aovs](Aov k) { return std::find(aovs.begin(), aovs.end(), k) != aovs.end(); };
  if (aovs_need_frame(aovs, 1)) flow[0] = flow_target(s.next.get(), has(Aov::FlowForward));
  if (aovs_need_frame(aovs, -1)) flow[1] = flow_target(s.previous.get(), has(Aov::FlowBackward));
}

// An object's map to the next frame: its transform there after the inverse of its transform here
// (rigid or affine motion), and which objects are deforming meshes, followed by their vertices.
RenderJob::FlowTarget RenderJob::flow_target(const FrameMotion* other, bool occlusion) const {
  FlowTarget to;
  to.wanted = true;
  to.occlusion = occlusion;
  if (!other) return to;
  to.camera = other->camera.get();
  to.accel = &accel;
  to.scene = other->geometry;
  if (to.scene && occlusion) {
    to.own = std::make_shared<const Accel>(*to.scene);
    to.accel = to.own.get();
  }
  to.there_from_here.resize(accel.object_count());
  for (uint32_t id = 0; id < accel.object_count(); ++id) {
    const Accel::Record& r = accel.record(id);
    const bool shape = r.kind == Accel::Record::Kind::Shape;
    const std::vector<Transform>& there = shape ? other->shapes : other->instances;
    const size_t here_count = shape ? scene.shapes.size() : scene.instances.size();
    if (there.size() != here_count || r.source >= there.size()) continue;
    const Transform& here = shape ? scene.shapes[r.source].world_from_object
                                  : scene.instances[r.source].world_from_object;
    to.there_from_here[id] = there[r.source] * here.inverse();
  }
  if (to.scene) find_deforming(to);
  return to;
}

bool RenderJob::same_triangles(uint32_t proto, const Scene& other) const {
  if (proto >= other.prototypes.size()) return false;
  const std::vector<TriangleMesh>&a = scene.prototypes[proto].meshes,
        &b = other.prototypes[proto].meshes;
  if (a.size() != b.size()) return false;
  for (size_t m = 0; m < a.size(); ++m)
    if (a[m].indices != b[m].indices || a[m].positions.size() != b[m].positions.size())
      return false;
  return true;
}

void RenderJob::find_deforming(FlowTarget& to) const {
  std::vector<uint8_t> deformed(scene.prototypes.size());
  for (const SceneRig& r : scene.rigs)
    if (r.animate && r.rig && r.rig->animated())
      for (const Deformer& d : r.rig->deformers) deformed.at(r.first_prototype + d.prototype) = 1;
  to.deforming.resize(accel.object_count());
  int flat_mesh = 0;  // a flattened instance's meshes are consecutive objects, one each
  for (uint32_t id = 0; id < accel.object_count(); ++id) {
    const Accel::Record& r = accel.record(id);
    const bool flat = r.kind == Accel::Record::Kind::FlatMesh;
    flat_mesh = flat && id > 0 && accel.record(id - 1).kind == r.kind &&
                        accel.record(id - 1).source == r.source
                    ? flat_mesh + 1
                    : 0;
    if (r.kind == Accel::Record::Kind::Shape || r.source >= scene.instances.size() ||
        r.source >= to.scene->instances.size())
      continue;
    const uint32_t proto = scene.instances[r.source].prototype;
    if (deformed[proto] && same_triangles(proto, *to.scene))
      to.deforming[id] = FlowTarget::Deforming{proto, r.source, flat ? flat_mesh : -1};
  }
}

std::optional<Vec3> RenderJob::moved_point(const FlowTarget& to, const Hit& hit) const {
  if (!to.there_from_here[hit.object_id]) return std::nullopt;
  if (to.deforming.empty() || !to.deforming[hit.object_id])
    return to.there_from_here[hit.object_id]->point(hit.p);
  const FlowTarget::Deforming& d = *to.deforming[hit.object_id];
  const uint32_t mesh = d.mesh >= 0 ? uint32_t(d.mesh) : hit.mesh;
  const TriangleMesh& a = scene.prototypes[d.prototype].meshes.at(mesh);
  const TriangleMesh& b = to.scene->prototypes[d.prototype].meshes.at(mesh);
  // The hit's barycentric coordinates in its triangle here (world space: flattened meshes are).
  const Transform& here = scene.instances[d.instance].world_from_object;
  const uint32_t* idx = &a.indices[size_t(hit.prim) * 3];
  const Vec3 p0 = here.point(Vec3(a.positions[idx[0]])),
             e1 = here.point(Vec3(a.positions[idx[1]])) - p0,
             e2 = here.point(Vec3(a.positions[idx[2]])) - p0, q = hit.p - p0;
  const double d00 = dot(e1, e1), d01 = dot(e1, e2), d11 = dot(e2, e2), den = d00 * d11 - d01 * d01;
  if (!(std::abs(den) > 0)) return std::nullopt;
  const double v = (d11 * dot(q, e1) - d01 * dot(q, e2)) / den,
               w = (d00 * dot(q, e2) - d01 * dot(q, e1)) / den;
  const Vec3 there = Vec3(b.positions[idx[0]]) * (1 - v - w) + Vec3(b.positions[idx[1]]) * v +
                     Vec3(b.positions[idx[2]]) * w;
  return to.scene->instances[d.instance].world_from_object.point(there);
}

double RenderJob::footprint_scale(uint32_t n) {
  return std::max(0.125, 1.0 / std::sqrt(double(std::max(1u, n))));
}

void RenderJob::fill_aovs(const Ray& ray, const Hit& hit, Vec2 uv, const Footprint& fp,
                          AovSample& a) const {
  // Every field for AOV layers; otherwise only the one the view shows.
  const bool all = film_aovs;
  const Material& m = *scene.materials[hit.material];
  a.hit = true;
  if (all || mode == RenderMode::Albedo)
    a.albedo =
        textured[hit.material] ? m.base_color.eval(texcoord_at(hit, fp)) : m.base_color.value;
  if (all || mode == RenderMode::Normal) a.normal = dot(hit.ns, ray.d) > 0 ? -hit.ns : hit.ns;
  if (all || mode == RenderMode::Position) a.position = hit.p;
  // Distance along the camera ray from its origin (dir is unit).
  if (all || mode == RenderMode::Depth) a.depth = hit.t;
  if (all || mode == RenderMode::Id) a.id = hit.object_id;
  if (all || mode == RenderMode::Uv) a.uv = hit.uv;
  if (all) fill_vision_aovs(hit, uv, a);
}

void RenderJob::fill_vision_aovs(const Hit& hit, Vec2 uv, AovSample& a) const {
  a.position_camera = camera_from_world.point(hit.p);
  a.depth_z = -a.position_camera.z;
  for (int d = 0; d < 2; ++d) {
    bool hid = false;
    a.moved[d] = flow[d].wanted && flow_at(flow[d], hit, uv, &a.flow[d], &hid);
    a.flow_valid[d] = a.moved[d] && !hid;
  }
}

bool RenderJob::flow_at(const FlowTarget& to, const Hit& hit, Vec2 uv, Vec2* flow,
                        bool* hidden_there) const {
  if (!to.camera) return false;
  const std::optional<Vec3> moved = moved_point(to, hit);
  if (!moved) return false;
  const Vec3 q = *moved;
  // Of several images (a point seen twice), the nearest to where it is now.
  bool found = false;
  double best = kInf;
  Vec2 there;
  for (const Vec2& at : to.camera->project(q)) {
    if (!(at.x >= 0 && at.x <= 1 && at.y >= 0 && at.y <= 1)) continue;
    const Vec2 d{(at.x - uv.x) * W, (at.y - uv.y) * H};
    const double d2 = d.x * d.x + d.y * d.y;
    if (d2 < best) best = d2, *flow = d, there = at, found = true;
  }
  *hidden_there = found && to.occlusion && hidden(to, q, there);
  return found;
}

// Traced from the origin of the other frame's camera ray at `at` to q: whatever it meets before
// q (short of it by a relative 1e-4: the surface at q itself is not an occluder) hides q.
bool RenderJob::hidden(const FlowTarget& to, const Vec3& q, Vec2 at) {
  const std::optional<CameraRay> r = to.camera->generate({at});
  if (!r) return true;
  Ray seg{r->org, q - r->org, 0, 1 - 1e-4};
  return to.accel->occluded(seg);
}

Color RenderJob::aov_beauty(const AovSample& a) const {
  if (!a.hit) return {};
  switch (mode) {
    case RenderMode::Albedo:
      return a.albedo;
    case RenderMode::Normal:
      return a.normal * 0.5 + Vec3(0.5);
    case RenderMode::Depth:
      return Color(a.depth);
    case RenderMode::Position:
      return a.position;
    case RenderMode::Id:
      return id_color(a.id);
    case RenderMode::Uv:
      return {a.uv.x, a.uv.y, 0};
    case RenderMode::Radiance:
      break;
  }
  return {};
}

double RenderJob::ray_time(const CameraSample& cs) const {
  return accel.has_motion() ? scene.camera->shutter_time(cs) : 0;
}

CameraSample RenderJob::camera_sample(Vec2 uv, Rng& rng) const {
  CameraSample cs;
  cs.uv = uv;
  if (scene.camera->uses_lens_or_time() || accel.has_motion()) {
    cs.lens = {rng.uniform(), rng.uniform()};
    cs.time = rng.uniform();
  }
  return cs;
}

SampleResult RenderJob::sample_at(Vec2 uv, Rng& rng, uint64_t& rays, double footprint) const {
  const CameraSample cs = camera_sample(uv, rng);
  const auto cam = scene.camera->generate(cs);
  if (!cam) return SampleResult{};  // no ray: transparent
  const Ray ray{cam->org, cam->dir, 0, kInf, ray_time(cs)};
  Hit h;
  ++rays;
  const bool found = accel.intersect(ray, &h);
  SampleResult out;
  finish(
      ray, [&] { return *cam; }, found ? &h : nullptr, uv, rng, rays, out, footprint);
  return out;
}

void RenderJob::lattice_samples(const Vec2* uv, const uint64_t* keys, const double* footprints,
                                const bool* use, SampleResult* out, uint64_t& rays,
                                CameraRayBatch* keep) const {
  constexpr int N = kCameraBatch;
  // A thread's scratch, set up once: zeroing sixteen hits and a ray batch for every batch of
  // samples was a twentieth of an adaptive render.
  struct Scratch {
    CameraSample cs[N];
    Rng rng[N];
    CameraRayBatch cam;
    Hit hits[N];
  };
  thread_local Scratch scratch;
  CameraSample* cs = scratch.cs;
  Rng* rng = scratch.rng;
  Hit* hits = scratch.hits;
  for (int k = 0; k < N; ++k) {
    rng[k] = Rng(keys[k], rs.seed);
    cs[k] = camera_sample(uv[k], rng[k]);
  }
  CameraRayBatch& cam = keep ? *keep : scratch.cam;
  scene.camera->generate_batch(cs, N, &cam);
  bool valid[N], found[N];
  for (int k = 0; k < N; ++k) valid[k] = use[k] && cam.valid[k];
  double time[N];
  for (int k = 0; k < N; ++k) time[k] = ray_time(cs[k]);
  accel.intersect16(cam.org, cam.dir, valid, hits, found, true, time);
  for (int k = 0; k < N; ++k) {
    if (!valid[k]) {
      out[k] = SampleResult{};  // no ray (or not wanted): transparent
      continue;
    }
    ++rays;
    finish(
        Ray{cam.origin(k), cam.direction(k), 0, kInf, time[k]}, [&] { return cam.ray(k); },
        found[k] ? &hits[k] : nullptr, uv[k], rng[k], rays, out[k], footprints[k]);
  }
}

}  // namespace anamorph
