// The scene's acceleration structure: Embree 3 BVHs over triangle meshes (single-use meshes
// flattened into the top level, shared ones instanced) and exact analytic shapes as Embree user
// geometry. Queries are const and thread-safe.
#pragma once

#include <embree3/rtcore.h>

#include <cstdint>
#include <memory>
#include <vector>

#include "math/transform.h"
#include "math/vec.h"
#include "scene/scene.h"

namespace anamorph {

struct Ray {
  Vec3 o, d;  // d need not be unit; t is in units of |d|
  double tmin = 0, tmax = kInf;
  double time = 0;  // in [0, 1] of the shutter: where moving objects are (object motion blur)
};

// Everything shading needs about a hit, in world space (double precision).
struct Hit {
  double t = kInf;
  Vec3 p;           // position
  Vec3 ng;          // geometric normal (unit, not flipped toward the ray)
  Vec3 ns;          // interpolated shading normal (unit, same hemisphere as ng)
  Vec2 uv;          // surface parameterization (mesh texture coordinates or shape parameters)
  Vec3 dpdu, dpdv;  // position derivatives w.r.t. uv (for texture footprints, normal maps)
  uint32_t material = 0;
  uint32_t object_id = 0;  // one id per scene object instance / shape (top-level geometry)
  uint32_t mesh = 0;       // mesh within an instanced prototype (0 otherwise)
  uint32_t prim = 0;       // triangle index within the mesh
  Vec3 p_object;           // position in object space (procedural textures)
  Vec3 n_object;           // geometric normal in object space
  // (For an object blurred by its motion, the transform at the frame: for texture footprints.)
  const Transform* object_from_world = nullptr;
  double time = 0;  // the ray's (rays leaving the hit take it on)
};

struct AccelStats {
  size_t unique_triangles = 0, instanced_triangles = 0, instances = 0, shapes = 0;
};

class Accel {
 public:
  explicit Accel(const Scene& scene);
  ~Accel();
  Accel(const Accel&) = delete;
  Accel& operator=(const Accel&) = delete;

  // `scene`, the one this was built from, posed at another frame (scene/scene_pose.h: the same
  // instances, prototypes and shapes; the animation's moving instances have new transforms, its
  // deforming prototypes new vertices): the moved instances take their transforms, the deformed
  // meshes are rebuilt alone, and the top level is built again over the rest. The queries then
  // answer as an Accel built anew from the posed scene would, bit for bit. False (nothing
  // changed): the posed scene would be built otherwise (an instance moved to where Embree cannot
  // carry it, or back), so build a new Accel.
  bool repose(const Scene& scene);

  bool intersect(const Ray& r, Hit* hit) const;
  bool occluded(const Ray& r) const;
  // Shadow rays that pass through a set of surfaces: the see-through surfaces of the Whitted
  // integrator (materials with transmission, Material::shadow_transmission, or alpha blend) or
  // the path tracer's alpha-blended ones (Material::blends). Whether a surface outside the set lies
  // on the ray, the set ignored (an any-hit query); and the nearest surface of the set on it, found
  // in a structure of its own that holds only them (cheap: usually a few objects, or none).
  enum class ShadowSet { Transmitting = 0, Blended = 1 };
  bool occluded_by_opaque(const Ray& r, ShadowSet set = ShadowSet::Transmitting) const;
  // Whether the ray (tmin to tmax) passes the set's bounding box: when it does not,
  // intersect_see_through would find nothing. Ask this first in a loop: a few multiplications,
  // where a Hit alone takes longer to set up, and a BVH of one object is a leaf that Embree
  // enters without testing its box.
  bool near_see_through(const Ray& r, ShadowSet set = ShadowSet::Transmitting) const;
  bool intersect_see_through(const Ray& r, Hit* hit, ShadowSet set = ShadowSet::Transmitting) const;
  bool has_see_through(ShadowSet set = ShadowSet::Transmitting) const {
    const SeeThrough& s = see_through_[int(set)];
    return s.scene || s.unbounded;
  }
  // Intersects 16 rays at once (packet API) for coherent primary rays; `valid[i]` masks lanes.
  void intersect16(const Ray* rays, const bool* valid, Hit* hits, bool* found) const;
  // The same for rays from t = 0 to infinity given as structure of arrays (org[c][i] is
  // component c of lane i), as camera batches hold them: no Ray per lane on the way in. Without
  // `surface`, a hit has only t, its ids and its material (renders of depth, ids or untextured
  // albedo need nothing else).
  // `time`: each lane's shutter time (null: all 0).
  void intersect16(const double (&org)[3][16], const double (&dir)[3][16], const bool* valid,
                   Hit* hits, bool* found, bool surface = true, const double* time = nullptr) const;
  Bounds3 bounds() const { return bounds_; }
  const AccelStats& stats() const { return stats_; }
  // Whether some geometry moves while the shutter is open (Instance::motion,
  // TriangleMesh::motion_positions): then rays need their time.
  bool has_motion() const { return has_motion_; }
  uint32_t object_count() const { return uint32_t(records_.size()); }

  // What each top-level geometry (object id) is; lights use it to find emissive triangles.
  struct Record {
    enum class Kind { FlatMesh, Instance, Shape };
    Kind kind = Kind::FlatMesh;
    const TriangleMesh* mesh = nullptr;    // FlatMesh (already in world space)
    const Prototype* proto = nullptr;      // Instance (object-space meshes)
    const AnalyticShape* shape = nullptr;  // Shape
    Transform world_from_object, object_from_world;
    std::vector<Transform> motion;  // Instance: world_from_object over the shutter (or none)
    // What it came from: an index into the scene's instances (FlatMesh, Instance) or shapes.
    uint32_t source = 0;
    uint32_t part = 0;  // FlatMesh: which mesh of the instance's prototype it is
  };
  const Record& record(uint32_t object_id) const { return *records_[object_id]; }

 private:
  void fill_hit(const Ray& r, float t, unsigned geom, unsigned prim, unsigned inst, float bu,
                float bv, Hit* hit, bool surface = true) const;
  bool nearest(RTCScene scene, const Ray& r, unsigned mask, Hit* hit) const;
  bool any(const Ray& r, unsigned mask) const;
  // The nearest unbounded shape the float ray (o, d) meets in (tmin, *tfar) among those `mask`
  // selects: *tfar becomes its distance, and its id is returned (RTC_INVALID_GEOMETRY_ID: none).
  unsigned nearest_unbounded(const Vec3& o, const Vec3& d, float tmin, float* tfar,
                             unsigned mask) const;
  struct MaskStore;
  // The constructor's steps.
  std::vector<bool> plan_flattening(const Scene& scene);
  bool same_plan(const Scene& scene) const;
  void attach(RTCGeometry g, std::unique_ptr<Record> rec, unsigned mask);
  void add_flat_meshes(const Scene& scene, const Instance& inst);
  void add_instance(const Scene& scene, const Instance& inst);
  void add_shape(const Scene& scene, const AnalyticShape& sh);
  void commit_and_bound();
  void repose_record(const Scene& scene, uint32_t id);

  RTCDevice device_ = nullptr;
  RTCScene top_ = nullptr;
  // Each shadow set's geometries of the top level, by the same ids, and their bounds; whether an
  // unbounded shape belongs to it.
  struct SeeThrough {
    RTCScene scene = nullptr;
    Bounds3 bounds;
    bool unbounded = false;
  };
  SeeThrough see_through_[2];
  // Shapes without bounds (infinite planes): in top_ only for their ids, disabled there, and
  // tested beside it by every query.
  struct Unbounded {
    unsigned id, mask;
    Vec3 point, normal;  // the plane in world space (the normal unit)
  };
  std::vector<Unbounded> unbounded_;
  Bounds3 unbounded_box_;  // (a finite square standing for them in bounds())
  std::vector<RTCScene> prototype_scenes_;
  std::vector<std::unique_ptr<Record>> records_;  // by top-level geomID
  std::vector<TriangleMesh> flat_meshes_;         // single-use meshes, moved to world space
  std::unique_ptr<MaskStore> masks_;              // alpha-mask filter data, referenced by Embree
  // For repose(): the instances' transforms as built, and the prototypes the animation deforms.
  // Also the plan: which instances are flattened, and which prototypes could be instanced.
  std::vector<Transform> placed_;
  std::vector<bool> deforming_, flatten_, in_world_;
  std::vector<int> uses_;
  Bounds3 bounds_;
  AccelStats stats_;
  bool has_motion_ = false;
};

}  // namespace anamorph
