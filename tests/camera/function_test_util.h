// Shared checks for the camera function tests: printing, finite differences of origin samples.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

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

// Samples at many positions through eval_batch, in packets of kCameraBatch (lane i of the
// result is positions[i]; ok[i] its flag).
inline std::vector<SurfaceSample> batch_samples(const OrgFunction& f,
                                                const std::vector<Vec2>& positions,
                                                std::vector<bool>* ok = nullptr) {
  std::vector<SurfaceSample> out(positions.size());
  if (ok) ok->assign(positions.size(), false);
  for (size_t i0 = 0; i0 < positions.size(); i0 += kCameraBatch) {
    const int n = int(std::min<size_t>(kCameraBatch, positions.size() - i0));
    double u[kCameraBatch], v[kCameraBatch];
    for (int k = 0; k < n; ++k) u[k] = positions[i0 + k].x, v[k] = positions[i0 + k].y;
    SurfaceBatch b;
    f.eval_batch(u, v, n, &b);
    for (int k = 0; k < n; ++k) {
      out[i0 + k] = b.lane(k);
      if (ok) (*ok)[i0 + k] = b.ok[k];
    }
  }
  return out;
}

// Every field of two samples equal, bit for bit (NaN never equals), printing the first that
// differs.
inline void expect_same_bits(const SurfaceSample& a, const SurfaceSample& b,
                             const std::string& what) {
  const std::pair<const char*, const Vec3 SurfaceSample::*> fields[] = {
      {"p", &SurfaceSample::p},         {"dpdu", &SurfaceSample::dpdu},
      {"dpdv", &SurfaceSample::dpdv},   {"n", &SurfaceSample::n},
      {"dndu", &SurfaceSample::dndu},   {"dndv", &SurfaceSample::dndv},
      {"dpduu", &SurfaceSample::dpduu}, {"dpduv", &SurfaceSample::dpduv},
      {"dpdvv", &SurfaceSample::dpdvv}};
  for (const auto& [name, field] : fields) {
    const Vec3 &x = a.*field, &y = b.*field;
    if (!(x.x == y.x && x.y == y.y && x.z == y.z)) {
      ADD_FAILURE() << what << ": " << name << " " << str(x) << " vs " << str(y);
      return;
    }
  }
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
