#include "accel/accel.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "accel/accel_internal.h"
#include "accel/motion.h"
#include "accel/shapes.h"
#include "math/frame.h"
#include "math/input_limits.h"
#include "math/simd.h"
#include "scene/scene_pose.h"

namespace anamorph {

using accel_detail::kBlend;
using accel_detail::kBlendSeeThrough;
using accel_detail::kOpaque;
using accel_detail::kSeeThrough;
using accel_detail::kSetMembers;
using accel_detail::shape_t;

namespace {

unsigned mask_of(const Material& m) {
  const bool transmits = m.shadow_transmission() > 0;
  if (m.blends()) return transmits ? kBlendSeeThrough : kBlend;
  return transmits ? kSeeThrough : kOpaque;
}

void embree_error(void*, RTCError code, const char* msg) {
  // Embree reports through this callback; failures here are programming or memory errors.
  throw std::runtime_error(fmt::format("Embree error {}: {}", int(code), msg ? msg : ""));
}

// Alpha-masked materials reject hits whose texture alpha is below the cutoff.
struct MaskData {
  const TriangleMesh* mesh;
  const Material* material;
};

void alpha_filter(const RTCFilterFunctionNArguments* args) {
  const auto* md = static_cast<const MaskData*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const unsigned prim = RTCHitN_primID(args->hit, args->N, i);
    const float bu = RTCHitN_u(args->hit, args->N, i), bv = RTCHitN_v(args->hit, args->N, i);
    const TriangleMesh& m = *md->mesh;
    if (m.uvs.empty()) continue;
    const uint32_t* idx = &m.indices[size_t(prim) * 3];
    const Vec2f a = m.uvs[idx[0]], b = m.uvs[idx[1]], c = m.uvs[idx[2]];
    TexCoord tc;
    tc.uv = {(1 - bu - bv) * a.x + bu * b.x + bv * c.x, (1 - bu - bv) * a.y + bu * b.y + bv * c.y};
    if (!md->material->opaque_at(tc)) args->valid[i] = 0;
  }
}

void shape_bounds(const RTCBoundsFunctionArguments* args) {
  const auto* rec = static_cast<const Accel::Record*>(args->geometryUserPtr);
  const Bounds3 b = rec->world_from_object.bounds(shape_object_bounds(*rec->shape));
  // Pad by a relative epsilon: float bounds must contain the double-precision surface.
  const Vec3 pad = max(b.hi - b.lo, Vec3(1.0)) * 1e-6;
  args->bounds_o->lower_x = float(b.lo.x - pad.x);
  args->bounds_o->lower_y = float(b.lo.y - pad.y);
  args->bounds_o->lower_z = float(b.lo.z - pad.z);
  args->bounds_o->upper_x = float(b.hi.x + pad.x);
  args->bounds_o->upper_y = float(b.hi.y + pad.y);
  args->bounds_o->upper_z = float(b.hi.z + pad.z);
}

template <bool kOcclusion, class Args>
void shape_query(const Args* args) {
  const auto* rec = static_cast<const Accel::Record*>(args->geometryUserPtr);
  const unsigned n = args->N;
  RTCRayN* ray;
  RTCHitN* hit = nullptr;
  if constexpr (kOcclusion) {
    ray = args->ray;
  } else {
    ray = RTCRayHitN_RayN(args->rayhit, n);
    hit = RTCRayHitN_HitN(args->rayhit, n);
  }
  for (unsigned i = 0; i < n; ++i) {
    if (args->valid[i] != -1) continue;
    const Vec3 o{RTCRayN_org_x(ray, n, i), RTCRayN_org_y(ray, n, i), RTCRayN_org_z(ray, n, i)};
    const Vec3 d{RTCRayN_dir_x(ray, n, i), RTCRayN_dir_y(ray, n, i), RTCRayN_dir_z(ray, n, i)};
    const double tmin = RTCRayN_tnear(ray, n, i), tmax = RTCRayN_tfar(ray, n, i);
    double t;
    if (!shape_t(*rec, o, d, tmin, tmax, &t)) continue;
    if constexpr (kOcclusion) {
      RTCRayN_tfar(ray, n, i) = -std::numeric_limits<float>::infinity();
    } else {
      const auto tf = float(t);
      if (!(tf < tmax)) continue;  // float rounding must not accept a farther hit
      RTCRayN_tfar(ray, n, i) = tf;
      // (No Ng: fill_hit computes the surface of the nearest hit alone, exactly; a normal here
      // would be computed for every closer candidate along the way.)
      RTCHitN_Ng_x(hit, n, i) = 0;
      RTCHitN_Ng_y(hit, n, i) = 0;
      RTCHitN_Ng_z(hit, n, i) = 0;
      RTCHitN_u(hit, n, i) = 0;
      RTCHitN_v(hit, n, i) = 0;
      RTCHitN_primID(hit, n, i) = args->primID;
      RTCHitN_geomID(hit, n, i) = args->geomID;
      RTCHitN_instID(hit, n, i, 0) = args->context->instID[0];
    }
  }
}

void shape_intersect(const RTCIntersectFunctionNArguments* args) { shape_query<false>(args); }
void shape_occluded(const RTCOccludedFunctionNArguments* args) { shape_query<true>(args); }

// Whether an instance can be an Embree instance: Embree carries each ray into the instance's own
// space, and a ray the world holds (math/input_limits.h) must stay there within what Embree takes
// (it asserts past 1.8e18). So the prototype's own coordinates lie within the world, and the
// inverse magnifies at most 1e5 times (2e12 from the instance's origin to 2e17). Other instances
// (a model in micrometres scaled by 1e-6, say) are moved to world space like a single-use one.
// (A moving instance: at each of its time steps.)
bool instanceable(const Instance& inst, bool prototype_within_world) {
  double magnification = 0;
  const auto magnify = [&](const Transform& t) {
    const auto& a = t.inverse_matrix().m;
    for (int r = 0; r < 3; ++r)
      magnification =
          std::max(magnification, std::abs(a[r][0]) + std::abs(a[r][1]) + std::abs(a[r][2]));
  };
  magnify(inst.world_from_object);
  for (const Transform& t : inst.motion) magnify(t);
  return prototype_within_world && magnification <= 1e5;
}

// Whether some instance moves or mesh deforms over the shutter.
bool blurs(const Scene& scene) {
  for (const Instance& inst : scene.instances)
    if (!inst.motion.empty()) return true;
  for (const Prototype& p : scene.prototypes)
    for (const TriangleMesh& m : p.meshes)
      if (!m.motion_positions.empty()) return true;
  return false;
}

bool within_world(const Prototype& proto) {
  for (const TriangleMesh& m : proto.meshes)
    for (const Vec3f& p : m.positions)
      if (!within_world(Vec3(p))) return false;
  return true;
}

void fill_vertices(RTCGeometry g, unsigned slot, const std::vector<Vec3f>& positions) {
  auto* v = static_cast<float*>(rtcGetGeometryBufferData(g, RTC_BUFFER_TYPE_VERTEX, slot));
  for (size_t i = 0; i < positions.size(); ++i) {
    v[3 * i] = positions[i].x;
    v[3 * i + 1] = positions[i].y;
    v[3 * i + 2] = positions[i].z;
  }
}

// The mesh's vertices and triangles into the geometry's buffers (made by make_triangles, of the
// mesh's sizes): one vertex buffer per time step when it deforms over the shutter.
void fill_triangles(RTCGeometry g, const TriangleMesh& m) {
  if (m.motion_positions.empty()) fill_vertices(g, 0, m.positions);
  for (size_t k = 0; k < m.motion_positions.size(); ++k)
    fill_vertices(g, unsigned(k), m.motion_positions[k]);
  auto* ix = static_cast<uint32_t*>(rtcGetGeometryBufferData(g, RTC_BUFFER_TYPE_INDEX, 0));
  std::copy(m.indices.begin(), m.indices.end(), ix);
}

RTCGeometry make_triangles(RTCDevice dev, const TriangleMesh& m, const Material& mat,
                           std::vector<std::unique_ptr<MaskData>>& masks) {
  RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetGeometryMask(g, mask_of(mat));
  const size_t steps = std::max<size_t>(1, m.motion_positions.size());
  if (steps > 1) rtcSetGeometryTimeStepCount(g, unsigned(steps));
  for (size_t k = 0; k < steps; ++k)
    rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, unsigned(k), RTC_FORMAT_FLOAT3,
                            3 * sizeof(float), m.positions.size());
  rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t),
                          m.triangle_count());
  fill_triangles(g, m);
  if (mat.alpha_masked()) {
    masks.push_back(std::make_unique<MaskData>(MaskData{&m, &mat}));
    rtcSetGeometryUserData(g, masks.back().get());
    rtcSetGeometryIntersectFilterFunction(g, alpha_filter);
    rtcSetGeometryOccludedFilterFunction(g, alpha_filter);
  }
  rtcCommitGeometry(g);
  return g;
}

void to_world(std::vector<Vec3f>& ps, std::vector<Vec3f>& ns, const Transform& world_from_object) {
  for (auto& p : ps) p = Vec3f(world_from_object.point(Vec3(p)));
  for (auto& nn : ns) nn = Vec3f(normalize(world_from_object.normal(Vec3(nn))));
}

// A mesh moved to world space (normals by the inverse transpose; triangles turned around when
// the transform mirrors). With `motion` (the instance's transforms over the shutter) or its own
// deformation, each time step moved by its transform. (A mirroring that changes over the shutter
// is taken at the frame.)
TriangleMesh flattened(const TriangleMesh& m, const Transform& world_from_object,
                       const std::vector<Transform>& motion = {}) {
  TriangleMesh w = m;
  to_world(w.positions, w.normals, world_from_object);
  if (!motion.empty() && w.motion_positions.empty()) {
    w.motion_positions.assign(motion.size(), m.positions);
    if (!m.normals.empty()) w.motion_normals.assign(motion.size(), m.normals);
  }
  for (size_t k = 0; k < w.motion_positions.size(); ++k) {
    std::vector<Vec3f> no_normals;
    to_world(w.motion_positions[k], k < w.motion_normals.size() ? w.motion_normals[k] : no_normals,
             motion.empty() ? world_from_object : motion[k]);
  }
  if (world_from_object.swaps_handedness())
    for (size_t t = 0; t < w.indices.size(); t += 3) std::swap(w.indices[t + 1], w.indices[t + 2]);
  return w;
}

// An instance's transform as Embree takes it (3x4, column-major), at time step `step`.
void set_transform(RTCGeometry g, const Transform& world_from_object, unsigned step = 0) {
  float xfm[12];
  const auto& a = world_from_object.matrix().m;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 3; ++r) xfm[c * 3 + r] = float(a[r][c]);
  rtcSetGeometryTransform(g, step, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, xfm);
}

}  // namespace

struct Accel::MaskStore {
  std::vector<std::unique_ptr<MaskData>> list;
};

// Which instances are flattened into the top level: single-use prototypes (a level of traversal
// saved for the common one-model scene) and instances Embree cannot carry (instanceable()). When
// the animation moves instances or deforms meshes, none is flattened for being single-use: the
// top level holds instances only, so that a frame moves them and rebuilds only it and the
// deformed meshes (repose()), not a BVH over every still triangle.
std::vector<bool> Accel::plan_flattening(const Scene& scene) {
  const std::vector<bool> moving = moving_instances(scene);
  const bool animated = std::find(moving.begin(), moving.end(), true) != moving.end() ||
                        std::find(deforming_.begin(), deforming_.end(), true) != deforming_.end();
  std::vector<int>& uses = uses_;
  uses.assign(scene.prototypes.size(), 0);
  for (const Instance& inst : scene.instances)
    uses[inst.prototype] += animated ? 2 : 1;  // (animated: each as if shared)
  std::vector<bool> flatten(scene.instances.size());
  in_world_.assign(scene.prototypes.size(), false);
  for (size_t p = 0; p < scene.prototypes.size(); ++p)
    in_world_[p] = uses[p] > 1 && within_world(scene.prototypes[p]);
  size_t flat_count = 0;
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    flatten[i] = uses[inst.prototype] == 1 || !instanceable(inst, in_world_[inst.prototype]);
    if (flatten[i]) flat_count += scene.prototypes[inst.prototype].meshes.size();
  }
  flat_meshes_.reserve(flat_count);  // (records point into it: no reallocation later)
  return flatten;
}

// Whether plan_flattening would plan the posed scene as it planned the scene built: an instance
// moved or deformed may have become one Embree cannot carry (or one it can).
bool Accel::same_plan(const Scene& scene) const {
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    const uint32_t p = inst.prototype;
    if (inst.world_from_object.matrix() == placed_[i].matrix() && !deforming_[p]) continue;
    if (uses_[p] == 1) continue;  // (never instanced: flattened, as before)
    const bool in_world = deforming_[p] ? within_world(scene.prototypes[p]) : in_world_[p];
    if (flatten_[i] != !instanceable(inst, in_world)) return false;
  }
  return true;
}

Accel::Accel(const Scene& scene) {
  // Embree picks its own kernels, unless ANAMORPH_ISA chose ours (math/simd.h): then the same set.
  device_ = rtcNewDevice(simd::embree_config());
  if (!device_)
    throw std::runtime_error(
        fmt::format("cannot create Embree device (error {})", int(rtcGetDeviceError(nullptr))));
  rtcSetDeviceErrorFunction(device_, embree_error, nullptr);
  top_ = rtcNewScene(device_);
  rtcSetSceneBuildQuality(top_, RTC_BUILD_QUALITY_HIGH);
  masks_ = std::make_unique<MaskStore>();
  prototype_scenes_.assign(scene.prototypes.size(), nullptr);

  deforming_ = deforming_prototypes(scene);  // (before the plan, which asks it)
  has_motion_ = blurs(scene);
  flatten_ = plan_flattening(scene);
  placed_.reserve(scene.instances.size());
  for (const Instance& inst : scene.instances) placed_.push_back(inst.world_from_object);
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    if (flatten_[i])
      add_flat_meshes(scene, scene.instances[i]);
    else
      add_instance(scene, scene.instances[i]);
  }
  for (const auto& sh : scene.shapes) add_shape(scene, sh);
  commit_and_bound();
}

// (A geometry with see-through parts joins the see-through structure too, by the same id, so
// that a hit there names the same record.)
void Accel::attach(RTCGeometry g, std::unique_ptr<Record> rec, unsigned mask) {
  const unsigned id = rtcAttachGeometry(top_, g);
  for (int set = 0; set < 2; ++set) {
    if (!(mask & kSetMembers[set])) continue;
    RTCScene& s = see_through_[set].scene;
    if (!s) s = rtcNewScene(device_);
    rtcAttachGeometryByID(s, g, id);
  }
  rtcReleaseGeometry(g);
  if (id != records_.size()) throw std::logic_error("Embree geometry ids are not sequential");
  records_.push_back(std::move(rec));
}

// Each mesh of the instance's prototype moved to world space once, as a top-level geometry of
// its own.
void Accel::add_flat_meshes(const Scene& scene, const Instance& inst) {
  const auto& meshes = scene.prototypes[inst.prototype].meshes;
  for (size_t k = 0; k < meshes.size(); ++k) {
    flat_meshes_.push_back(flattened(meshes[k], inst.world_from_object, inst.motion));
    const TriangleMesh& fm = flat_meshes_.back();
    const Material& mat = *scene.materials[fm.material];
    RTCGeometry g = make_triangles(device_, fm, mat, masks_->list);
    auto rec = std::make_unique<Record>();
    rec->kind = Record::Kind::FlatMesh;
    rec->mesh = &fm;
    rec->source = uint32_t(&inst - scene.instances.data());
    rec->part = uint32_t(k);
    attach(g, std::move(rec), mask_of(mat));
    stats_.unique_triangles += fm.triangle_count();
    stats_.instanced_triangles += fm.triangle_count();
  }
}

// An Embree instance of the prototype's scene (built on its first use).
void Accel::add_instance(const Scene& scene, const Instance& inst) {
  const Prototype& proto = scene.prototypes[inst.prototype];
  RTCScene& ps = prototype_scenes_[inst.prototype];
  if (!ps) {
    ps = rtcNewScene(device_);
    rtcSetSceneBuildQuality(ps, RTC_BUILD_QUALITY_HIGH);
    for (const auto& m : proto.meshes) {
      RTCGeometry g = make_triangles(device_, m, *scene.materials[m.material], masks_->list);
      rtcAttachGeometry(ps, g);
      rtcReleaseGeometry(g);
      stats_.unique_triangles += m.triangle_count();
    }
    rtcCommitScene(ps);
  }
  RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);
  rtcSetGeometryInstancedScene(g, ps);
  unsigned mask = 0;  // (an instance holds what its meshes hold; each keeps its own mask)
  for (const auto& m : proto.meshes) mask |= mask_of(*scene.materials[m.material]);
  rtcSetGeometryMask(g, mask);
  if (inst.motion.empty()) {
    set_transform(g, inst.world_from_object);
  } else {
    rtcSetGeometryTimeStepCount(g, unsigned(inst.motion.size()));
    for (size_t k = 0; k < inst.motion.size(); ++k) set_transform(g, inst.motion[k], unsigned(k));
  }
  rtcCommitGeometry(g);
  auto rec = std::make_unique<Record>();
  rec->kind = Record::Kind::Instance;
  rec->proto = &proto;
  rec->motion = inst.motion;
  rec->source = uint32_t(&inst - scene.instances.data());
  rec->world_from_object = inst.world_from_object;
  rec->object_from_world = inst.world_from_object.inverse();
  attach(g, std::move(rec), mask);
  stats_.instances++;
  for (const auto& m : proto.meshes) stats_.instanced_triangles += m.triangle_count();
}

// An analytic shape as a user geometry with its exact intersection.
void Accel::add_shape(const Scene& scene, const AnalyticShape& sh) {
  auto rec = std::make_unique<Record>();
  rec->kind = Record::Kind::Shape;
  rec->shape = &sh;
  rec->source = uint32_t(&sh - scene.shapes.data());
  rec->world_from_object = sh.world_from_object;
  rec->object_from_world = sh.world_from_object.inverse();
  RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_USER);
  rtcSetGeometryUserPrimitiveCount(g, 1);
  rtcSetGeometryUserData(g, rec.get());
  rtcSetGeometryBoundsFunction(g, shape_bounds, nullptr);
  rtcSetGeometryIntersectFunction(g, shape_intersect);
  rtcSetGeometryOccludedFunction(g, shape_occluded);
  const unsigned mask = mask_of(*scene.materials[sh.material]);
  rtcSetGeometryMask(g, mask);
  rtcCommitGeometry(g);
  stats_.shapes++;
  if (sh.kind != AnalyticShape::Kind::Plane) return attach(g, std::move(rec), mask);
  // An infinite plane's box holds every ray: in the BVH it would be a leaf that every ray
  // enters and calls back. It is tested beside the BVH instead, first, so that its hit also
  // shortens the BVH's query (a ray toward the floor skips all beyond it).
  const unsigned id = unsigned(records_.size());
  unbounded_.push_back({id, mask, rec->world_from_object.point({0, 0, 0}),
                        normalize(rec->world_from_object.normal({0, 1, 0}))});
  unbounded_box_.extend(rec->world_from_object.bounds(shape_object_bounds(sh)));
  for (int set = 0; set < 2; ++set)
    if (mask & kSetMembers[set]) see_through_[set].unbounded = true;
  rtcDisableGeometry(g);
  const unsigned got = rtcAttachGeometry(top_, g);  // (for its id and record only)
  rtcReleaseGeometry(g);
  if (got != id) throw std::logic_error("Embree geometry ids are not sequential");
  records_.push_back(std::move(rec));
}

void Accel::commit_and_bound() {
  rtcCommitScene(top_);
  for (SeeThrough& st : see_through_) {
    if (!st.scene) continue;
    rtcCommitScene(st.scene);
    RTCBounds sb;
    rtcGetSceneBounds(st.scene, &sb);
    st.bounds = {{sb.lower_x, sb.lower_y, sb.lower_z}, {sb.upper_x, sb.upper_y, sb.upper_z}};
  }
  RTCBounds b;
  rtcGetSceneBounds(top_, &b);
  if (records_.size() > unbounded_.size()) {
    bounds_.extend({b.lower_x, b.lower_y, b.lower_z});
    bounds_.extend({b.upper_x, b.upper_y, b.upper_z});
  }
  if (!unbounded_.empty()) {
    bounds_.extend(unbounded_box_.lo);
    bounds_.extend(unbounded_box_.hi);
  }
}

bool Accel::repose(const Scene& scene) {
  if (scene.instances.size() != placed_.size() || scene.prototypes.size() != deforming_.size())
    throw std::logic_error("Accel::repose: not the scene it was built from");
  // (Blurred frames are built anew: their time steps need not be those built.)
  if (has_motion_ || blurs(scene) || !same_plan(scene)) return false;
  for (size_t p = 0; p < prototype_scenes_.size(); ++p) {
    if (!deforming_[p] || !prototype_scenes_[p]) continue;
    const auto& meshes = scene.prototypes[p].meshes;
    for (size_t k = 0; k < meshes.size(); ++k) {
      RTCGeometry g = rtcGetGeometry(prototype_scenes_[p], unsigned(k));
      fill_triangles(g, meshes[k]);
      rtcUpdateGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0);
      rtcCommitGeometry(g);
    }
    rtcCommitScene(prototype_scenes_[p]);
  }
  for (uint32_t id = 0; id < records_.size(); ++id) repose_record(scene, id);
  for (size_t i = 0; i < placed_.size(); ++i) placed_[i] = scene.instances[i].world_from_object;
  bounds_ = {};
  commit_and_bound();  // (the see-through structures share the moved geometries: committed too)
  return true;
}

// One top-level geometry after repose() changed its instance or prototype: a flattened mesh moved
// to world space again, an instance given its transform (and committed again when its prototype
// deformed, so that the top level takes its new bounds).
void Accel::repose_record(const Scene& scene, uint32_t id) {
  Record& rec = *records_[id];
  if (rec.kind == Record::Kind::Shape) return;
  const Instance& inst = scene.instances[rec.source];
  const bool moved = !(inst.world_from_object.matrix() == placed_[rec.source].matrix());
  if (!moved && !deforming_[inst.prototype]) return;
  RTCGeometry g = rtcGetGeometry(top_, id);
  if (rec.kind == Record::Kind::FlatMesh) {
    auto& fm = flat_meshes_[size_t(rec.mesh - flat_meshes_.data())];
    fm = flattened(scene.prototypes[inst.prototype].meshes[rec.part], inst.world_from_object);
    fill_triangles(g, fm);
    rtcUpdateGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0);
    rtcUpdateGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0);
  } else {
    set_transform(g, inst.world_from_object);
    rec.world_from_object = inst.world_from_object;
    rec.object_from_world = inst.world_from_object.inverse();
  }
  rtcCommitGeometry(g);
}

Accel::~Accel() {
  for (SeeThrough& st : see_through_)
    if (st.scene) rtcReleaseScene(st.scene);
  if (top_) rtcReleaseScene(top_);
  for (RTCScene s : prototype_scenes_)
    if (s) rtcReleaseScene(s);
  if (device_) rtcReleaseDevice(device_);
}

namespace {

// dp/du, dp/dv from a triangle's uv layout (a frame about its normal ng when the layout is
// degenerate).
void triangle_tangents(const Vec3& p0, const Vec3& p1, const Vec3& p2, Vec2 uv0, Vec2 uv1, Vec2 uv2,
                       const Vec3& ng, Vec3* dpdu, Vec3* dpdv) {
  const Vec2 duv02 = uv0 - uv2, duv12 = uv1 - uv2;
  const Vec3 dp02 = p0 - p2, dp12 = p1 - p2;
  const double det = duv02.x * duv12.y - duv02.y * duv12.x;
  if (std::abs(det) > 1e-20) {
    const double inv = 1 / det;
    *dpdu = (dp02 * duv12.y - dp12 * duv02.y) * inv;
    *dpdv = (dp12 * duv02.x - dp02 * duv12.x) * inv;
  } else {
    const Frame f = Frame::from_normal(normalize(ng));
    *dpdu = f.s;
    *dpdv = f.t;
  }
}

// A triangle's vertices at time `time` (a deforming mesh's interpolated between its steps).
void vertices_at(const TriangleMesh& m, const uint32_t* idx, double time, Vec3* p0, Vec3* p1,
                 Vec3* p2) {
  if (m.motion_positions.empty()) {
    *p0 = Vec3(m.positions[idx[0]]), *p1 = Vec3(m.positions[idx[1]]);
    *p2 = Vec3(m.positions[idx[2]]);
    return;
  }
  const auto s = accel_detail::time_segment(time, m.motion_positions.size());
  *p0 = accel_detail::lerp_vertex(m.motion_positions, idx[0], s);
  *p1 = accel_detail::lerp_vertex(m.motion_positions, idx[1], s);
  *p2 = accel_detail::lerp_vertex(m.motion_positions, idx[2], s);
}

// The interpolated (not normalized) vertex normal at barycentrics (w, bu, bv) and `time`.
Vec3 shading_normal(const TriangleMesh& m, const uint32_t* idx, double time, double w, float bu,
                    float bv) {
  if (m.motion_normals.empty())
    return Vec3(m.normals[idx[0]]) * w + Vec3(m.normals[idx[1]]) * double(bu) +
           Vec3(m.normals[idx[2]]) * double(bv);
  const auto s = accel_detail::time_segment(time, m.motion_normals.size());
  return accel_detail::lerp_vertex(m.motion_normals, idx[0], s) * w +
         accel_detail::lerp_vertex(m.motion_normals, idx[1], s) * double(bu) +
         accel_detail::lerp_vertex(m.motion_normals, idx[2], s) * double(bv);
}

uint32_t material_of(const Accel::Record& rec, unsigned geom) {
  using Kind = Accel::Record::Kind;
  return rec.kind == Kind::Shape      ? rec.shape->material
         : rec.kind == Kind::FlatMesh ? rec.mesh->material
                                      : rec.proto->meshes[geom].material;
}

// The shading normal: the interpolated vertex normal `ns` turned to ng's side; ng itself without
// vertex normals (`smooth` false) or where they cancel.
Vec3 facing_normal(bool smooth, Vec3 ns, const Vec3& ng) {
  if (!smooth) return ng;
  ns = length(ns) > 0 ? normalize(ns) : ng;
  return dot(ns, ng) < 0 ? -ns : ns;
}

// An analytic shape's hit, recomputed in double from the object-space ray for an exact point.
void fill_shape_hit(const Accel::Record& rec, const Ray& r, float t, Hit* h) {
  const AnalyticShape& s = *rec.shape;
  const Vec3 oo = rec.object_from_world.point(r.o), od = rec.object_from_world.vector(r.d);
  Vec3 po = oo + od * double(t);
  const ShapeSurface ss = shape_surface(s, po);
  h->p = rec.world_from_object.point(po);
  h->ng = normalize(rec.world_from_object.normal(ss.n));
  h->ns = h->ng;
  h->uv = ss.uv;
  h->dpdu = rec.world_from_object.vector(ss.dpdu);
  h->dpdv = rec.world_from_object.vector(ss.dpdv);
  h->material = s.material;
  h->p_object = po;
  h->n_object = ss.n;
  h->object_from_world = &rec.object_from_world;
}

}  // namespace

void Accel::fill_hit(const Ray& r, float t, unsigned geom, unsigned prim, unsigned inst, float bu,
                     float bv, Hit* h, bool surface) const {
  h->t = t;
  h->time = r.time;
  const unsigned top_id = inst != RTC_INVALID_GEOMETRY_ID ? inst : geom;
  const Record& rec = *records_[top_id];
  h->object_id = top_id;
  h->mesh = inst != RTC_INVALID_GEOMETRY_ID ? geom : 0;
  h->prim = prim;
  if (!surface) {
    h->material = material_of(rec, geom);
    return;
  }
  if (rec.kind == Record::Kind::Shape) return fill_shape_hit(rec, r, t, h);
  const TriangleMesh* m;
  const Transform* xf = nullptr;
  std::optional<Transform> moved;  // (an instance's transform at the ray's time)
  if (rec.kind == Record::Kind::FlatMesh) {
    m = rec.mesh;
  } else {
    m = &rec.proto->meshes[geom];
    xf = &rec.world_from_object;
    if (!rec.motion.empty()) xf = &moved.emplace(accel_detail::transform_at(rec.motion, r.time));
  }
  const uint32_t* idx = &m->indices[size_t(prim) * 3];
  Vec3 p0, p1, p2;
  vertices_at(*m, idx, r.time, &p0, &p1, &p2);
  const double w = 1.0 - bu - bv;
  Vec3 po = p0 * w + p1 * double(bu) + p2 * double(bv);
  Vec3 ngo = cross(p1 - p0, p2 - p0);
  const auto uv_of = [&](int k) {  // (without uvs: the triangle's own (0,0), (1,0), (0,1))
    return m->uvs.empty() ? Vec2{double(k == 1), double(k == 2)}
                          : Vec2{m->uvs[idx[k]].x, m->uvs[idx[k]].y};
  };
  const Vec2 uv0 = uv_of(0), uv1 = uv_of(1), uv2 = uv_of(2);
  h->uv = uv0 * w + uv1 * double(bu) + uv2 * double(bv);
  Vec3 dpdu, dpdv;
  triangle_tangents(p0, p1, p2, uv0, uv1, uv2, ngo, &dpdu, &dpdv);
  const bool smooth = !m->normals.empty();
  Vec3 ns;
  if (smooth) ns = shading_normal(*m, idx, r.time, w, bu, bv);
  h->p_object = po;
  h->n_object = normalize(ngo);
  if (xf) {
    po = xf->point(po);
    h->ng = normalize(xf->normal(ngo));
    if (smooth) ns = xf->normal(ns);
    dpdu = xf->vector(dpdu);
    dpdv = xf->vector(dpdv);
    h->object_from_world = &rec.object_from_world;
  } else {
    h->ng = h->n_object;
    h->object_from_world = nullptr;
  }
  h->p = po;
  h->ns = facing_normal(smooth, ns, h->ng);
  h->dpdu = dpdu;
  h->dpdv = dpdv;
  h->material = m->material;
}

}  // namespace anamorph
