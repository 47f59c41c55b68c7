#include "camera/ray_field.h"

#include <algorithm>

#include "math/parallel.h"

namespace anamorph {

namespace {

// Batch lane i of `b` to ray `k` of the arrays.
void store(const CameraRayBatch& b, int i, size_t k, const RayArrays& out) {
  const bool ok = b.valid[i];
  const auto put = [&](double* a, const double(&src)[3][CameraRayBatch::N]) {
    if (!a) return;
    for (int c = 0; c < 3; ++c) a[3 * k + size_t(c)] = ok ? src[c][i] : 0.0;
  };
  put(out.org, b.org);
  put(out.dir, b.dir);
  put(out.dorg_du, b.dorg_du);
  put(out.dorg_dv, b.dorg_dv);
  put(out.ddir_du, b.ddir_du);
  put(out.ddir_dv, b.ddir_dv);
  if (out.valid) out.valid[k] = ok ? 1 : 0;
}

// Rays first..first+n-1 (n <= kCameraBatch) from the samples sample(k).
template <class SampleAt>
void batch(const Camera& cam, size_t first, int n, const SampleAt& sample, const RayArrays& out) {
  CameraSample s[kCameraBatch];
  for (int i = 0; i < n; ++i) s[i] = sample(first + size_t(i));
  CameraRayBatch b;
  cam.generate_batch(s, n, &b);
  for (int i = 0; i < n; ++i) store(b, i, first + size_t(i), out);
}

template <class SampleAt>
void all_rays(const Camera& cam, size_t n, const SampleAt& sample, const RayArrays& out) {
  constexpr size_t kGrain = 64 * kCameraBatch;
  parallel_chunks(0, n, kGrain, [&](size_t lo, size_t hi) {
    for (size_t k = lo; k < hi; k += kCameraBatch)
      batch(cam, k, int(std::min<size_t>(kCameraBatch, hi - k)), sample, out);
  });
}

// The pixel-centre sample of pixel (x, y) of a width x height image.
CameraSample pixel_centre(size_t x, size_t y, int width, int height) {
  CameraSample s;
  s.uv = {(double(x) + 0.5) / width, (double(y) + 0.5) / height};
  return s;
}

}  // namespace

void generate_rays(const Camera& cam, size_t n, const SampleArrays& in, const RayArrays& out) {
  all_rays(
      cam, n,
      [&](size_t k) {
        CameraSample s;
        s.uv = {in.u[k], in.v[k]};
        if (in.lens_u) s.lens.x = in.lens_u[k];
        if (in.lens_v) s.lens.y = in.lens_v[k];
        if (in.time) s.time = in.time[k];
        return s;
      },
      out);
}

void generate_ray_field(const Camera& cam, int width, int height, const RayArrays& out) {
  const size_t w = size_t(width);
  all_rays(
      cam, w * size_t(height), [&](size_t k) { return pixel_centre(k % w, k / w, width, height); },
      out);
}

void generate_pixel_rays(const Camera& cam, int width, int height, int x0, int y0, int x1, int y1,
                         const RayArrays& out) {
  const size_t w = size_t(std::max(0, x1 - x0)), n = w * size_t(std::max(0, y1 - y0));
  const auto sample = [&](size_t k) {
    return pixel_centre(size_t(x0) + k % w, size_t(y0) + k / w, width, height);
  };
  for (size_t k = 0; k < n; k += kCameraBatch)
    batch(cam, k, int(std::min<size_t>(kCameraBatch, n - k)), sample, out);
}

Projections project_points(const Camera& cam, size_t n, const double* xyz) {
  std::vector<std::vector<Vec2>> found(n);
  parallel_chunks(0, n, 256, [&](size_t lo, size_t hi) {
    for (size_t i = lo; i < hi; ++i)
      found[i] = cam.project({xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]});
  });
  Projections p;
  p.offsets.reserve(n + 1);
  p.offsets.push_back(0);
  for (const auto& f : found) {
    for (const Vec2& uv : f) p.uv.insert(p.uv.end(), {uv.x, uv.y});
    p.offsets.push_back(p.uv.size() / 2);
  }
  return p;
}

}  // namespace anamorph
