// Shared checks for the camera function tests: printing, finite differences of origin samples.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>

#include "camera/functions.h"

namespace anamorph::test {

inline std::string str(const Vec3& v) {
  std::ostringstream os;
  os.precision(12);
  os << "(" << v.x << ", " << v.y << ", " << v.z << ")";
  return os.str();
}

// Concatenates anything streamable (avoids GCC 12's -Wrestrict false positive on "lit" + string).
template <class... T>
std::string cat(const T&... parts) {
  std::ostringstream os;
  os.precision(17);  // numbers round-trip exactly through TOML text
  (os << ... << parts);
  return os.str();
}

inline SurfaceSample sample(const OrgFunction& f, Vec2 uv) {
  SurfaceSample s;
  EXPECT_TRUE(f.eval(uv, &s)) << "no sample at (" << uv.x << ", " << uv.y << ")";
  return s;
}

// |a - b| <= tol * max(1, |b|), printing both on failure.
inline void expect_close(const Vec3& a, const Vec3& b, double tol, const std::string& what) {
  const double err = length(a - b), scale = std::max(1.0, length(b));
  EXPECT_LE(err, tol * scale) << what << ": got " << str(a) << ", expected " << str(b) << " (error "
                              << err << ")";
}

// Every analytic derivative of an origin sample against central differences of the function:
// p -> dpdu, dpdv; dpdu, dpdv -> second derivatives; n -> dndu, dndv.
inline void expect_derivatives_match(const OrgFunction& f, Vec2 uv, double tol = 1e-6,
                                     double h = 1e-5) {
  const SurfaceSample s = sample(f, uv);
  const SurfaceSample up = sample(f, {uv.x + h, uv.y}), um = sample(f, {uv.x - h, uv.y});
  const SurfaceSample vp = sample(f, {uv.x, uv.y + h}), vm = sample(f, {uv.x, uv.y - h});
  const std::string at = cat(" at (", uv.x, ", ", uv.y, ")");
  const auto fd = [&](const Vec3& a, const Vec3& b) { return (a - b) / (2 * h); };
  expect_close(s.dpdu, fd(up.p, um.p), tol, cat("dpdu", at));
  expect_close(s.dpdv, fd(vp.p, vm.p), tol, cat("dpdv", at));
  expect_close(s.dpduu, fd(up.dpdu, um.dpdu), tol, cat("dpduu", at));
  expect_close(s.dpduv, fd(vp.dpdu, vm.dpdu), tol, cat("dpduv (from dpdu)", at));
  expect_close(s.dpduv, fd(up.dpdv, um.dpdv), tol, cat("dpduv (from dpdv)", at));
  expect_close(s.dpdvv, fd(vp.dpdv, vm.dpdv), tol, cat("dpdvv", at));
  expect_close(s.dndu, fd(up.n, um.n), tol, cat("dndu", at));
  expect_close(s.dndv, fd(vp.n, vm.n), tol, cat("dndv", at));
}

// Unit normal, orthogonal to both first derivatives.
inline void expect_normal_valid(const OrgFunction& f, Vec2 uv, double tol = 1e-9) {
  const SurfaceSample s = sample(f, uv);
  const std::string at = cat(" at (", uv.x, ", ", uv.y, ")");
  EXPECT_NEAR(length(s.n), 1, tol) << "n = " << str(s.n) << at;
  const double lu = std::max(length(s.dpdu), 1e-300), lv = std::max(length(s.dpdv), 1e-300);
  EXPECT_NEAR(dot(s.n, s.dpdu) / lu, 0, tol) << "n " << str(s.n) << " dpdu " << str(s.dpdu) << at;
  EXPECT_NEAR(dot(s.n, s.dpdv) / lv, 0, tol) << "n " << str(s.n) << " dpdv " << str(s.dpdv) << at;
}

}  // namespace anamorph::test
