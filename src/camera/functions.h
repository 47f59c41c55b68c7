// The two building blocks of a virtual camera (the paper's "sets org and dir"). Both are pure
// functions of the normalized image position (u, v) in [0,1]^2; each maps (u, v) linearly onto
// its own parameter ranges.
#pragma once

#include <memory>
#include <span>
#include <string_view>

#include "camera/params.h"
#include "math/vec.h"

namespace anamorph {

// A point of the origin surface with its partial derivatives with respect to image (u, v) and its
// unit normal (zero where a surface has no normal, e.g. a single point).
struct SurfaceSample {
  Vec3 p, dpdu, dpdv, n;
};

// A (not necessarily unit) direction with its derivatives with respect to image (u, v).
struct DirSample {
  Vec3 d, dd_du, dd_dv;
};

class OrgFunction {
 public:
  virtual ~OrgFunction() = default;
  // Returns false for *no ray* (outside the function's domain).
  virtual bool eval(Vec2 uv, SurfaceSample* out) const = 0;
};

class DirFunction {
 public:
  virtual ~DirFunction() = default;
  // `org` is the (possibly coin-deformed) origin sample: dependent directions (normal, tangent)
  // read it. Returns false for *no ray*.
  virtual bool eval(Vec2 uv, const SurfaceSample& org, DirSample* out) const = 0;
};

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

}  // namespace anamorph
