// The acceleration structure's queries: nearest hits, any-hit tests, packets, and the
// see-through walk of shadow rays, each with the unbounded shapes tested beside the BVH.
#include <cmath>
#include <limits>

#include "accel/accel.h"
#include "accel/accel_internal.h"
#include "accel/shapes.h"
#include "math/input_limits.h"

namespace anamorph {

using accel_detail::kAll;
using accel_detail::kSetMembers;
using accel_detail::set_blockers;
using accel_detail::shape_t;

// Embree's far distance for ours: beyond float's range is infinity, not float's overflow.
static float far_of(double tmax) {
  return tmax >= double(std::numeric_limits<float>::max()) ? std::numeric_limits<float>::infinity()
                                                           : float(tmax);
}

// Whether Embree may take the ray (math/input_limits.h): it asserts, aborting the process, on an
// origin or direction beyond 1.8e18. The scene reader keeps every object within the world and the
// camera gives no ray from beyond it, so this holds for every ray the renderer makes; a ray that
// would not (a bug, a scene built in code) misses the BVH instead of ending the process.
static bool embree_may_take(const RTCRay& r) {
  return ray_in_range({r.org_x, r.org_y, r.org_z}, {r.dir_x, r.dir_y, r.dir_z}) && r.tnear >= 0 &&
         !std::isnan(r.tfar);
}

static void set_ray(RTCRay& ray, const Ray& r, unsigned mask = kAll) {
  ray.org_x = float(r.o.x);
  ray.org_y = float(r.o.y);
  ray.org_z = float(r.o.z);
  ray.dir_x = float(r.d.x);
  ray.dir_y = float(r.d.y);
  ray.dir_z = float(r.d.z);
  ray.tnear = float(r.tmin);
  ray.tfar = far_of(r.tmax);
  ray.time = float(r.time);
  ray.mask = mask;
  ray.id = 0;
  ray.flags = 0;
}

unsigned Accel::nearest_unbounded(const Vec3& o, const Vec3& d, float tmin, float* tfar,
                                  unsigned mask) const {
  unsigned found = RTC_INVALID_GEOMETRY_ID;
  for (const Unbounded& u : unbounded_) {
    // (In world space: a plane is a point and a normal, and t is the same in every space.)
    const double dn = dot(d, u.normal), num = dot(u.point - o, u.normal);
    if (!(u.mask & mask) || dn == 0) continue;
    // (Behind the origin when num and dn differ in sign: most shadow rays leave the floor, and
    // this sends them on without a division.)
    if (tmin >= 0 && !(num * dn > 0)) continue;
    const double t = num / dn;
    if (!(t > tmin && t < *tfar)) continue;
    // (A plane ends where the world does: a grazing ray's hit far out would start rays there.)
    if (!within_world(o + d * t)) continue;
    const auto tf = float(t);
    if (!(tf < *tfar)) continue;  // (as the callbacks do: float rounding must not go farther)
    *tfar = tf;
    found = u.id;
  }
  return found;
}

static Vec3 org_of(const RTCRay& r) { return {r.org_x, r.org_y, r.org_z}; }
static Vec3 dir_of(const RTCRay& r) { return {r.dir_x, r.dir_y, r.dir_z}; }

// The nearest hit of `r` in `scene` among the geometries `mask` selects, the unbounded shapes
// first (their hit bounds the BVH's query; a BVH hit then is nearer).
bool Accel::nearest(RTCScene scene, const Ray& r, unsigned mask, Hit* hit) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh;
  set_ray(rh.ray, r, mask);
  const unsigned plane = unbounded_.empty() ? RTC_INVALID_GEOMETRY_ID
                                            : nearest_unbounded(org_of(rh.ray), dir_of(rh.ray),
                                                                rh.ray.tnear, &rh.ray.tfar, mask);
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  if (scene && embree_may_take(rh.ray)) rtcIntersect1(scene, &ctx, &rh);
  if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID)
    fill_hit(r, rh.ray.tfar, rh.hit.geomID, rh.hit.primID, rh.hit.instID[0], rh.hit.u, rh.hit.v,
             hit);
  else if (plane != RTC_INVALID_GEOMETRY_ID)
    fill_hit(r, rh.ray.tfar, plane, 0, RTC_INVALID_GEOMETRY_ID, 0, 0, hit);
  else
    return false;
  return true;
}

bool Accel::any(const Ray& r, unsigned mask) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRay ray;
  set_ray(ray, r, mask);
  if (!unbounded_.empty()) {
    float tfar = ray.tfar;
    if (nearest_unbounded(org_of(ray), dir_of(ray), ray.tnear, &tfar, mask) !=
        RTC_INVALID_GEOMETRY_ID)
      return true;
  }
  if (!embree_may_take(ray)) return false;
  rtcOccluded1(top_, &ctx, &ray);
  return ray.tfar < 0;
}

bool Accel::intersect(const Ray& r, Hit* hit) const { return nearest(top_, r, kAll, hit); }
bool Accel::occluded(const Ray& r) const { return any(r, kAll); }
bool Accel::occluded_by_opaque(const Ray& r, ShadowSet set) const {
  return any(r, set_blockers(int(set)));
}
// Whether the segment of `r` from tmin to tmax meets box `b` (the slab test).
static bool meets(const Bounds3& b, const Ray& r) {
  double t0 = r.tmin, t1 = r.tmax;
  for (int a = 0; a < 3; ++a) {
    const double inv = 1 / r.d[a];
    double tn = (b.lo[a] - r.o[a]) * inv, tf = (b.hi[a] - r.o[a]) * inv;
    if (tn > tf) std::swap(tn, tf);
    t0 = tn > t0 ? tn : t0;
    t1 = tf < t1 ? tf : t1;
    if (!(t0 <= t1)) return false;  // (a NaN from 0 * inf leaves t0, t1: it rules nothing out)
  }
  return true;
}

bool Accel::near_see_through(const Ray& r, ShadowSet set) const {
  const SeeThrough& st = see_through_[int(set)];
  return st.unbounded || (st.scene && meets(st.bounds, r));
}

bool Accel::intersect_see_through(const Ray& r, Hit* hit, ShadowSet set) const {
  return nearest(see_through_[int(set)].scene, r, kSetMembers[int(set)], hit);
}

// One packet: `load(rh)` writes the lanes' origins, directions, extents and times, `bound(o, d,
// tmin, &tfar)` tests what is not in the BVH (shortening tfar; the id it hit, or none; called only
// when `bounded`, i.e. the scene has unbounded shapes), the rest is set here.
template <int N, class RayHitN, class Load, class Bound, class F>
static void intersect_packet(const bool* valid, bool* found, RTCScene scene, Load&& load,
                             bool bounded, Bound&& bound, F&& fill,
                             void (*trace)(const int*, RTCScene, RTCIntersectContext*, RayHitN*)) {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  alignas(64) RayHitN rh;
  alignas(64) int v[N];
  unsigned beside[N];
  load(rh);
  // Which lanes Embree may take: float comparisons only, so that the loop vectorizes (with the
  // byte-sized `valid` in it, or a call per lane, it stayed scalar: a tenth of a primary-ray
  // render's time).
  alignas(64) int in_range[N];
  for (int i = 0; i < N; ++i)
    in_range[i] = ray_in_range_f(rh.ray.org_x[i], rh.ray.org_y[i], rh.ray.org_z[i], rh.ray.dir_x[i],
                                 rh.ray.dir_y[i], rh.ray.dir_z[i]);
  bool take[N];
  bool any = false;
  for (int i = 0; i < N; ++i) {
    take[i] = valid[i] && in_range[i];
    any |= take[i];
    v[i] = take[i] ? -1 : 0;
    // A lane not taken holds a finite ray all the same: Debian's Embree 3.13 on AVX2 (16-wide
    // packets run as two 8-wide halves) asserted `ray.valid()` on a packet whose every lane was
    // masked off but held NaN directions (a table camera's no-ray region), aborting the process.
    if (!take[i]) {
      rh.ray.org_x[i] = rh.ray.org_y[i] = rh.ray.org_z[i] = 0.0f;
      rh.ray.dir_x[i] = rh.ray.dir_y[i] = 0.0f;
      rh.ray.dir_z[i] = 1.0f;
      rh.ray.tnear[i] = rh.ray.tfar[i] = 0.0f;
    }
    rh.ray.mask[i] = kAll;
    rh.ray.id[i] = unsigned(i);
    rh.ray.flags[i] = 0;
    rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
    beside[i] = RTC_INVALID_GEOMETRY_ID;
  }
  if (bounded)
    for (int i = 0; i < N; ++i)
      if (take[i])
        beside[i] = bound(Vec3{rh.ray.org_x[i], rh.ray.org_y[i], rh.ray.org_z[i]},
                          Vec3{rh.ray.dir_x[i], rh.ray.dir_y[i], rh.ray.dir_z[i]}, rh.ray.tnear[i],
                          &rh.ray.tfar[i]);
  if (any) trace(v, scene, &ctx, &rh);
  for (int i = 0; i < N; ++i) {
    const bool in_bvh = rh.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID;
    found[i] = take[i] && (in_bvh || beside[i] != RTC_INVALID_GEOMETRY_ID);
    if (!found[i]) continue;
    if (in_bvh)
      fill(i, rh.ray.tfar[i], rh.hit.geomID[i], rh.hit.primID[i], rh.hit.instID[0][i], rh.hit.u[i],
           rh.hit.v[i]);
    else
      fill(i, rh.ray.tfar[i], beside[i], 0, RTC_INVALID_GEOMETRY_ID, 0.f, 0.f);
  }
}

void Accel::intersect16(const Ray* rays, const bool* valid, Hit* hits, bool* found) const {
  intersect_packet<16, RTCRayHit16>(
      valid, found, top_,
      [&](RTCRayHit16& rh) {
        for (int i = 0; i < 16; ++i) {
          const Ray& r = rays[i];
          rh.ray.org_x[i] = float(r.o.x);
          rh.ray.org_y[i] = float(r.o.y);
          rh.ray.org_z[i] = float(r.o.z);
          rh.ray.dir_x[i] = float(r.d.x);
          rh.ray.dir_y[i] = float(r.d.y);
          rh.ray.dir_z[i] = float(r.d.z);
          rh.ray.tnear[i] = float(r.tmin);
          rh.ray.tfar[i] = far_of(r.tmax);
          rh.ray.time[i] = float(r.time);
        }
      },
      !unbounded_.empty(),
      [&](const Vec3& o, const Vec3& d, float tmin, float* tfar) {
        return nearest_unbounded(o, d, tmin, tfar, kAll);
      },
      [&](int i, float t, unsigned g, unsigned p, unsigned in, float u, float v) {
        fill_hit(rays[i], t, g, p, in, u, v, &hits[i]);
      },
      rtcIntersect16);
}

void Accel::intersect16(const double (&org)[3][16], const double (&dir)[3][16], const bool* valid,
                        Hit* hits, bool* found, bool surface, const double* time) const {
  intersect_packet<16, RTCRayHit16>(
      valid, found, top_,
      [&](RTCRayHit16& rh) {
        // Component by component: conversions the compiler turns into vector instructions.
        for (int i = 0; i < 16; ++i) rh.ray.org_x[i] = float(org[0][i]);
        for (int i = 0; i < 16; ++i) rh.ray.org_y[i] = float(org[1][i]);
        for (int i = 0; i < 16; ++i) rh.ray.org_z[i] = float(org[2][i]);
        for (int i = 0; i < 16; ++i) rh.ray.dir_x[i] = float(dir[0][i]);
        for (int i = 0; i < 16; ++i) rh.ray.dir_y[i] = float(dir[1][i]);
        for (int i = 0; i < 16; ++i) rh.ray.dir_z[i] = float(dir[2][i]);
        for (int i = 0; i < 16; ++i) rh.ray.tnear[i] = 0.0f;
        for (int i = 0; i < 16; ++i) rh.ray.tfar[i] = std::numeric_limits<float>::infinity();
        for (int i = 0; i < 16; ++i) rh.ray.time[i] = time ? float(time[i]) : 0.0f;
      },
      !unbounded_.empty(),
      [&](const Vec3& o, const Vec3& d, float tmin, float* tfar) {
        return nearest_unbounded(o, d, tmin, tfar, kAll);
      },
      [&](int i, float t, unsigned g, unsigned p, unsigned in, float u, float v) {
        const Ray r{{org[0][i], org[1][i], org[2][i]},
                    {dir[0][i], dir[1][i], dir[2][i]},
                    0,
                    kInf,
                    time ? time[i] : 0};
        fill_hit(r, t, g, p, in, u, v, &hits[i], surface);
      },
      rtcIntersect16);
}

}  // namespace anamorph
