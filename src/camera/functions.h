// The two building blocks of a virtual camera (the paper's "sets org and dir"). Both are pure
// functions of the normalized image position (u, v) in [0,1]^2; each maps (u, v) linearly onto
// its own parameter ranges (u_range / v_range; a decreasing range mirrors the image).
//
// Conventions shared by every function: right-handed world, +y up, the default view looks along
// -z; image u runs left to right and v top to bottom. Open surfaces (plane, splines, expression,
// mesh) take their normal from d/du x d/dv of their *own* parameters, which is the side the image
// looks at when the surface is laid out as seen by the viewer (u right, v down). Closed surfaces
// (sphere, torus, ...) have outward normals. Reversing a range never flips the normal, and every
// surface has `flip_normal` to look the other way.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "camera/camera.h"
#include "math/vec.h"
#include "params/params.h"

namespace anamorph {

// A point of the origin surface and its derivatives, all with respect to *image* (u, v), so a
// pixel's footprint is the derivative times 1/width (1/height). Every origin function fills every
// field (zero where it does not exist).
struct SurfaceSample {
  Vec3 p;                    // the point
  Vec3 dpdu, dpdv;           // first derivatives
  Vec3 n;                    // unit normal (zero where the surface has none, e.g. a single point)
  Vec3 dndu, dndv;           // derivatives of the unit normal n (ray differentials of dir = normal)
  Vec3 dpduu, dpduv, dpdvv;  // second derivatives (ray differentials of tangent directions)
};

// All fields zero. (`*s = SurfaceSample{}` compiles to `rep stos`, whose start-up cost is most of
// a cheap origin function's time; this is a few vector stores.)
inline void clear(SurfaceSample* s) {
  s->p = s->dpdu = s->dpdv = s->n = s->dndu = s->dndv = s->dpduu = s->dpduv = s->dpdvv = Vec3{};
}

// Up to kCameraBatch origin samples in structure-of-arrays form (the fields of SurfaceSample, one
// array per component), so that origin kernels and the dependent directions reading them
// vectorize. ok[i] false: no ray; that lane's fields are then all zero (dir functions read
// defined values).
struct SurfaceBatch {
  static constexpr int N = kCameraBatch;
  double p[3][N], dpdu[3][N], dpdv[3][N], n[3][N], dndu[3][N], dndv[3][N];
  double dpduu[3][N], dpduv[3][N], dpdvv[3][N];
  bool ok[N];

  static Vec3 at(const double (&a)[3][N], int i) { return {a[0][i], a[1][i], a[2][i]}; }
  static void put(double (&a)[3][N], int i, const Vec3& x) {
    a[0][i] = x.x, a[1][i] = x.y, a[2][i] = x.z;
  }
  SurfaceSample lane(int i) const {
    return {at(p, i),    at(dpdu, i),  at(dpdv, i),  at(n, i),    at(dndu, i),
            at(dndv, i), at(dpduu, i), at(dpduv, i), at(dpdvv, i)};
  }
  void set(int i, const SurfaceSample& s) {
    put(p, i, s.p), put(dpdu, i, s.dpdu), put(dpdv, i, s.dpdv), put(n, i, s.n);
    put(dndu, i, s.dndu), put(dndv, i, s.dndv), put(dpduu, i, s.dpduu), put(dpduv, i, s.dpduv);
    put(dpdvv, i, s.dpdvv);
  }
};

// A (not necessarily unit) direction with its derivatives with respect to image (u, v).
struct DirSample {
  Vec3 d, dd_du, dd_dv;
};

// Up to kCameraBatch directions in structure-of-arrays form, so that loops over them vectorize
// (the renderer asks for its 4x4 primary-ray packets at once).
struct DirBatch {
  double d[3][kCameraBatch], du[3][kCameraBatch], dv[3][kCameraBatch];
  bool ok[kCameraBatch];
  void set(int i, const DirSample& s) {
    d[0][i] = s.d.x, d[1][i] = s.d.y, d[2][i] = s.d.z;
    du[0][i] = s.dd_du.x, du[1][i] = s.dd_du.y, du[2][i] = s.dd_du.z;
    dv[0][i] = s.dd_dv.x, dv[1][i] = s.dd_dv.y, dv[2][i] = s.dd_dv.z;
  }
  DirSample lane(int i) const {
    return {{d[0][i], d[1][i], d[2][i]},
            {du[0][i], du[1][i], du[2][i]},
            {dv[0][i], dv[1][i], dv[2][i]}};
  }
};

class OrgFunction {
 public:
  virtual ~OrgFunction() = default;
  // Returns false for *no ray* (outside the function's domain). Const, thread-safe, allocates
  // nothing.
  virtual bool eval(Vec2 uv, SurfaceSample* out) const = 0;

  // n <= kCameraBatch samples at (u[i], v[i]): lane i and ok[i] as eval would give them, bit for
  // bit (a lane without ray all zero). The default loops over eval.
  virtual void eval_batch(const double* u, const double* v, int n, SurfaceBatch* out) const;
  // The same with only p, dpdu, dpdv and ok filled in (bit for bit as eval_batch), the other
  // fields unspecified: what the camera asks for when its direction function reads no more of
  // the origin (DirFunction::reads_org_beyond_first_order), since writing the normal and second
  // derivatives costs more stores than the ray itself. The default is eval_batch.
  virtual void eval_batch_first_order(const double* u, const double* v, int n,
                                      SurfaceBatch* out) const {
    eval_batch(u, v, n, out);
  }
};

class DirFunction {
 public:
  virtual ~DirFunction() = default;
  // `org` is the origin sample at the same (u, v), before coins (they deform the finished ray
  // field): dependent directions (normal, tangent) read it. Returns false for *no ray*. Const,
  // thread-safe, allocates nothing.
  virtual bool eval(Vec2 uv, const SurfaceSample& org, DirSample* out) const = 0;

  // n <= kCameraBatch directions at (u[i], v[i]) with the origin samples in org's lanes,
  // exactly as eval gives them (out->ok[i] is eval's result). The default loops over eval;
  // functions whose math vectorizes override it.
  virtual void eval_batch(const double* u, const double* v, int n, const SurfaceBatch& org,
                          DirBatch* out) const;

  // True when every direction this function returns is of unit length and dd_du, dd_dv are the
  // derivatives of that unit vector (so they are perpendicular to it): the camera then skips
  // normalizing (a square root and a division per ray, most of a cheap camera's cost) whenever
  // its rig keeps lengths. A zero direction still means no ray.
  virtual bool unit_length() const { return false; }

  // Whether eval reads more of its origin sample than p, dpdu and dpdv (the normal, its
  // derivatives or the second derivatives, as the dependent directions do). When false the
  // camera gets its origins from OrgFunction::eval_batch_first_order.
  virtual bool reads_org_beyond_first_order() const { return true; }
};

// Batches as a loop over eval. With F a final class the calls are direct (no virtual dispatch
// per sample) and can inline; the base classes' default eval_batch use them with F = the base.
template <class F>
void org_batch_by_eval(const F& f, const double* u, const double* v, int n, SurfaceBatch* out) {
  for (int i = 0; i < n; ++i) {
    SurfaceSample s;
    out->ok[i] = f.eval({u[i], v[i]}, &s);
    if (!out->ok[i]) clear(&s);
    out->set(i, s);
  }
}
template <class F>
void dir_batch_by_eval(const F& f, const double* u, const double* v, int n, const SurfaceBatch& org,
                       DirBatch* out) {
  for (int i = 0; i < n; ++i) {
    DirSample d;
    out->ok[i] = f.eval({u[i], v[i]}, org.lane(i), &d);
    out->set(i, out->ok[i] ? d : DirSample{});
  }
}

// Bases for functions whose batch is that loop: `class F final : public OrgFunctionLoop<F>`.
template <class Derived>
class OrgFunctionLoop : public OrgFunction {
 public:
  void eval_batch(const double* u, const double* v, int n, SurfaceBatch* out) const override {
    org_batch_by_eval(static_cast<const Derived&>(*this), u, v, n, out);
  }
};
template <class Derived>
class DirFunctionLoop : public DirFunction {
 public:
  void eval_batch(const double* u, const double* v, int n, const SurfaceBatch& org,
                  DirBatch* out) const override {
    dir_batch_by_eval(static_cast<const Derived&>(*this), u, v, n, org, out);
  }
};

// The other way round, for functions whose batch is a kernel: eval as a batch of one, so single
// samples and batches give the same bits.
inline bool eval_as_batch_of_one(const OrgFunction& f, Vec2 uv, SurfaceSample* out) {
  SurfaceBatch b;
  f.eval_batch(&uv.x, &uv.y, 1, &b);
  *out = b.lane(0);
  return b.ok[0];
}
inline bool eval_as_batch_of_one(const DirFunction& f, Vec2 uv, const SurfaceSample& org,
                                 DirSample* out) {
  SurfaceBatch o;
  o.set(0, org);
  DirBatch b;
  f.eval_batch(&uv.x, &uv.y, 1, o, &b);
  *out = b.lane(0);
  return b.ok[0];
}

// A linear map of t in [0,1] onto [a, b]; b < a reverses the parameter.
struct ParamRange {
  double a = 0, b = 1;
  double operator()(double t) const { return a + (b - a) * t; }
  double scale() const { return b - a; }
};

// Registry entries: the one source of truth for each function's name, doc and parameters.
struct OrgFunctionInfo {
  std::string_view name;
  std::string_view doc;
  std::span<const ParamSpec> params;
  std::unique_ptr<OrgFunction> (*create)(const ParamValues&);
};
struct DirFunctionInfo {
  std::string_view name;
  std::string_view doc;
  std::span<const ParamSpec> params;
  std::unique_ptr<DirFunction> (*create)(const ParamValues&);
};

std::span<const OrgFunctionInfo> org_functions();
std::span<const DirFunctionInfo> dir_functions();
const OrgFunctionInfo* find_org_function(std::string_view name);
const DirFunctionInfo* find_dir_function(std::string_view name);
// The `type` key of an origin / direction function table, its choices the functions' names.
const ParamSpec& org_type_spec();
const ParamSpec& dir_type_spec();

// Checks values against a parameter table: required keys present, numbers finite and within
// [min, max] (each component of vectors and lists), strings among `choices`. Factories call it
// first, so functions built in code (presets, tests) are held to the same rules as parsed ones.
// Throws ParamError naming the key.
void check_params(std::span<const ParamSpec> specs, const ParamValues& values);

// Builds a function from TOML text holding some of its keys, the rest from the table's defaults,
// e.g. make_org("sphere", "radius = 2\ncenter = [0, 1, 0]"). For presets, tests and tools; scene
// files go through the scene parser, which adds file positions to errors. Throws ParamError
// (unknown type or key, bad value).
ParamValues params_from_toml(std::span<const ParamSpec> specs, std::string_view toml_text);
std::unique_ptr<OrgFunction> make_org(std::string_view type, std::string_view toml_text = {});
std::unique_ptr<DirFunction> make_dir(std::string_view type, std::string_view toml_text = {});

// Markdown reference of every origin and direction function: a section per function with its
// doc and a table name | type | default | range | meaning (for docs/cameras.md).
std::string function_params_markdown();

}  // namespace anamorph
