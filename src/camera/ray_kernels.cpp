#include "camera/ray_kernels.h"

#include <cmath>

#include "math/simd.h"

namespace anamorph {

void AffineField::sample(Vec2 uv, SurfaceSample* s, DirSample* d) const {
  const auto field = [&uv](const Vec3& a0, const Vec3& au, const Vec3& av) {
    return Vec3{at(a0.x, au.x, av.x, uv.x, uv.y), at(a0.y, au.y, av.y, uv.x, uv.y),
                at(a0.z, au.z, av.z, uv.x, uv.y)};
  };
  clear(s);
  s->p = field(o0, o_u, o_v);
  s->dpdu = o_u;
  s->dpdv = o_v;
  *d = DirSample{field(d0, d_u, d_v), d_u, d_v};
}

namespace {

// Where a kernel's lanes take their raw field from. kUniformOrgDerivs: the origin's derivatives
// are the same in every lane (written from lane 0's, or the constants).

// The affine closed form at the packet's positions.
struct AffineSource {
  static constexpr bool kUniformOrgDerivs = true;
  AffineField f;  // a copy: stores to the output cannot alias it
  const double* u;
  const double* v;
  [[gnu::always_inline]] Vec3 field(const Vec3& a0, const Vec3& au, const Vec3& av, int i) const {
    return {AffineField::at(a0.x, au.x, av.x, u[i], v[i]),
            AffineField::at(a0.y, au.y, av.y, u[i], v[i]),
            AffineField::at(a0.z, au.z, av.z, u[i], v[i])};
  }
  [[gnu::always_inline]] Vec3 p(int i) const { return field(f.o0, f.o_u, f.o_v, i); }
  [[gnu::always_inline]] Vec3 dpdu(int) const { return f.o_u; }
  [[gnu::always_inline]] Vec3 dpdv(int) const { return f.o_v; }
  [[gnu::always_inline]] Vec3 d(int i) const { return field(f.d0, f.d_u, f.d_v, i); }
  [[gnu::always_inline]] Vec3 du(int) const { return f.d_u; }
  [[gnu::always_inline]] Vec3 dv(int) const { return f.d_v; }
  [[gnu::always_inline]] bool ok(int) const { return true; }
};

// The batches the origin and direction functions wrote; a point origin's one sample (lane 0)
// stands for every lane.
template <bool kPointOrg>
struct FunctionSource {
  static constexpr bool kUniformOrgDerivs = kPointOrg;
  const SurfaceBatch& org;
  const DirBatch& dir;
  [[gnu::always_inline]] static Vec3 at(const double (&a)[3][kCameraBatch], int i) {
    return {a[0][i], a[1][i], a[2][i]};
  }
  [[gnu::always_inline]] Vec3 p(int i) const { return at(org.p, kPointOrg ? 0 : i); }
  [[gnu::always_inline]] Vec3 dpdu(int i) const { return at(org.dpdu, i); }
  [[gnu::always_inline]] Vec3 dpdv(int i) const { return at(org.dpdv, i); }
  [[gnu::always_inline]] Vec3 d(int i) const { return at(dir.d, i); }
  [[gnu::always_inline]] Vec3 du(int i) const { return at(dir.du, i); }
  [[gnu::always_inline]] Vec3 dv(int i) const { return at(dir.dv, i); }
  [[gnu::always_inline]] bool ok(int i) const { return dir.ok[i] & (kPointOrg || org.ok[i]); }
};

[[gnu::always_inline]] inline void put(double (&a)[3][kCameraBatch], int i, const Vec3& x) {
  a[0][i] = x.x, a[1][i] = x.y, a[2][i] = x.z;
}

// The one ray loop: the rig (kIdentity: none, whose products would only add zeros), then the
// unit direction with its derivatives (kUnit: the directions are unit vectors with perpendicular
// derivatives, DirFunction::unit_length, and the rig keeps lengths, so normalizing would only
// round them again). A zero-length or non-finite direction, or a non-finite origin, means no
// ray (never NaN); x * 0 == 0 holds exactly for finite x. Written straight into the batch's
// arrays; the masks in loops of their own (bool stores from double lanes keep GCC from
// vectorizing a loop; comparisons and ANDs of bools each vectorize, mixed they stay scalar).
template <class Source, bool kIdentity, bool kUnit>
[[gnu::always_inline]] inline void ray_lanes(const Source& src, const AffineRig& t, int n,
                                             CameraRayBatch* __restrict out) {
  const AffineRig rig = t;  // a local copy: stores to `out` cannot alias it
  const auto& m = rig.m;
  const auto vec = [&](const Vec3& a) __attribute__((always_inline)) {
    if (kIdentity) return a;
    return Vec3{m[0][0] * a.x + m[0][1] * a.y + m[0][2] * a.z,
                m[1][0] * a.x + m[1][1] * a.y + m[1][2] * a.z,
                m[2][0] * a.x + m[2][1] * a.y + m[2][2] * a.z};
  };
  const auto point = [&](const Vec3& a) __attribute__((always_inline)) {
    if (kIdentity) return a;
    const Vec3 r = vec(a);
    return Vec3{r.x + m[0][3], r.y + m[1][3], r.z + m[2][3]};
  };
  constexpr int N = kCameraBatch;
  alignas(64) double lens[N], finite[N];
  if (!Source::kUniformOrgDerivs)
    for (int i = 0; i < n; ++i)
      put(out->dorg_du, i, vec(src.dpdu(i))), put(out->dorg_dv, i, vec(src.dpdv(i)));
  const Vec3 uniform_du = Source::kUniformOrgDerivs ? vec(src.dpdu(0)) : Vec3{},
             uniform_dv = Source::kUniformOrgDerivs ? vec(src.dpdv(0)) : Vec3{};
  for (int i = 0; i < n; ++i) {
    const Vec3 o = point(src.p(i)), d = vec(src.d(i)), du = vec(src.du(i)), dv = vec(src.dv(i));
    put(out->org, i, o);
    if (Source::kUniformOrgDerivs)
      put(out->dorg_du, i, uniform_du), put(out->dorg_dv, i, uniform_dv);
    double dx = d.x, dy = d.y, dz = d.z, ux = du.x, uy = du.y, uz = du.z, vx = dv.x, vy = dv.y,
           vz = dv.z;
    if (kUnit) {
      lens[i] = dx * dx + dy * dy + dz * dz;  // 1, or 0 for a function's zero vector
      finite[i] = (dx + dy + dz) * 0 + (o.x + o.y + o.z) * 0;
    } else {
      const double len = std::sqrt(dx * dx + dy * dy + dz * dz);
      lens[i] = len;
      finite[i] = len * 0 + (o.x + o.y + o.z) * 0;
      unit_direction<false>(len, dx, dy, dz, ux, uy, uz, vx, vy, vz);
    }
    put(out->dir, i, {dx, dy, dz});
    put(out->ddir_du, i, {ux, uy, uz});
    put(out->ddir_dv, i, {vx, vy, vz});
  }
  for (int i = 0; i < n; ++i) out->valid[i] = (lens[i] > 0) & (finite[i] == 0);
  for (int i = 0; i < n; ++i) out->valid[i] = out->valid[i] & src.ok(i);
}

// Each kernel is inlined with n = 16 (full packets: full vectors, no remainder loop) and n = 1
// (generate(): straight-line code) as constants.
ANAMORPH_KERNEL_BODY void affine_body(const AffineField& f, const double* u, const double* v, int n,
                                      CameraRayBatch* out) {
  const AffineSource src{f, u, v};
  with_trip_count<kCameraBatch>(
      n, [&](auto c) __attribute__((always_inline)) {
        ray_lanes<AffineSource, true, false>(src, AffineRig{}, c, out);
      });
}

template <bool kPointOrg, bool kIdentity, bool kUnit>
ANAMORPH_KERNEL_BODY void finish_body(const AffineRig& rig, const SurfaceBatch& org,
                                      const DirBatch& dir, int n, CameraRayBatch* out) {
  const FunctionSource<kPointOrg> src{org, dir};
  with_trip_count<kCameraBatch>(
      n, [&](auto c) __attribute__((always_inline)) {
        ray_lanes<FunctionSource<kPointOrg>, kIdentity, kUnit>(src, rig, c, out);
      });
}

template <bool kPointOrg, bool kIdentity, bool kUnit>
FinishKernel finish_of() {
  return simd::Kernel<finish_body<kPointOrg, kIdentity, kUnit>>::get();
}

}  // namespace

AffineKernel affine_kernel() { return simd::Kernel<affine_body>::get(); }

FinishKernel finish_kernel(FinishKind k) {
  using Get = FinishKernel (*)();
  static constexpr Get kTable[2][2][2] = {
      {{finish_of<false, false, false>, finish_of<false, false, true>},
       {finish_of<false, true, false>, finish_of<false, true, true>}},
      {{finish_of<true, false, false>, finish_of<true, false, true>},
       {finish_of<true, true, false>, finish_of<true, true, true>}}};
  return kTable[k.point_org][k.identity_rig][k.unit_dirs]();
}

}  // namespace anamorph
