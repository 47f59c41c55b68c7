#include "camera/stmap.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "math/parallel.h"

namespace anamorph {

namespace {

std::optional<CameraRay> ray_at(const Camera& camera, double x, double y, int width, int height) {
  CameraSample s;
  s.uv = {x / width, y / height};
  return camera.generate(s);
}

void put_pixel(StMap* m, size_t i, Vec2 uv, const Vec3& d, bool valid) {
  m->st[2 * i] = valid ? float(uv.x) : 0.0f;
  m->st[2 * i + 1] = valid ? float(1 - uv.y) : 0.0f;
  m->alpha[i] = valid ? 1.0f : 0.0f;
  for (int k = 0; k < 3; ++k) m->direction[3 * i + size_t(k)] = float(d[k]);
}

StMap empty_map(int width, int height) {
  StMap m;
  m.width = width, m.height = height;
  const size_t n = size_t(width) * size_t(height);
  m.st.assign(2 * n, 0.0f), m.alpha.assign(n, 0.0f), m.direction.assign(3 * n, 0.0f);
  return m;
}

double max_abs(const Vec3& v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); }

}  // namespace

Vec3 central_origin(const Camera& camera, int width, int height) {
  constexpr int kGrid = 33;
  std::optional<Vec3> first;
  Vec2 first_px;
  for (int j = 0; j < kGrid; ++j)
    for (int i = 0; i < kGrid; ++i) {
      const double x = (i + 0.5) / kGrid * width, y = (j + 0.5) / kGrid * height;
      const auto r = ray_at(camera, x, y, width, height);
      if (!r) continue;
      if (!first) {
        first = r->org, first_px = {x, y};
        continue;
      }
      const double tol = 1e-9 * (1 + max_abs(*first));
      if (max_abs(r->org - *first) > tol)
        throw NonCentralCamera(fmt::format(
            "the camera is not central: its rays leave different points (pixel ({:g}, {:g}) from "
            "({:.9g}, {:.9g}, {:.9g}), pixel ({:g}, {:g}) from ({:.9g}, {:.9g}, {:.9g})), so it is "
            "not a reprojection of directions; STMaps and warps need one eye point",
            first_px.x, first_px.y, first->x, first->y, first->z, x, y, r->org.x, r->org.y,
            r->org.z));
    }
  if (!first) throw NonCentralCamera("the camera has no ray anywhere in the image");
  return *first;
}

Vec3 mean_origin(const Camera& camera, int width, int height) {
  constexpr int kGrid = 33;
  Vec3 sum;
  int n = 0;
  for (int j = 0; j < kGrid; ++j)
    for (int i = 0; i < kGrid; ++i)
      if (const auto r =
              ray_at(camera, (i + 0.5) / kGrid * width, (j + 0.5) / kGrid * height, width, height))
        sum += r->org, ++n;
  if (n == 0) throw NonCentralCamera("the camera has no ray anywhere in the image");
  return sum / double(n);
}

std::optional<CameraRay> seen_from_eye(const CameraRay& r, const DepthSphere& s) {
  // |o + t d - eye| = depth, the larger root (the ray leaving the sphere).
  const Vec3 oc = r.org - s.eye;
  const double b = dot(oc, r.dir), c = dot(oc, oc) - s.depth * s.depth;
  const double disc = b * b - c;
  if (!(disc >= 0)) return std::nullopt;
  const double t = -b + std::sqrt(disc);
  if (!(t > 0)) return std::nullopt;
  const Vec3 n = (oc + r.dir * t) / s.depth;  // the unit direction from the eye
  const double nd = dot(n, r.dir);
  if (!(nd > 0)) return std::nullopt;
  // On the sphere dP.n = 0, so dt = -n.(do + t dd) / n.d and the direction moves by dP / depth.
  const auto moved = [&](const Vec3& dorg, const Vec3& ddir) {
    const Vec3 a = dorg + ddir * t;
    return (a - r.dir * (dot(n, a) / nd)) / s.depth;
  };
  return CameraRay{
      s.eye, n, Vec3{}, Vec3{}, moved(r.dorg_du, r.ddir_du), moved(r.dorg_dv, r.ddir_dv)};
}

DepthSphere map_sphere(const Camera& camera, int width, int height, std::optional<double> depth) {
  if (depth) return {mean_origin(camera, width, height), *depth};
  return {central_origin(camera, width, height), 1};
}

StMap forward_stmap(const Camera& camera, const SourceProjection& source, int width, int height,
                    const std::optional<DepthSphere>& sphere) {
  StMap m = empty_map(width, height);
  parallel_for_each(0, height, [&](int y) {
    for (int x = 0; x < width; ++x) {
      const size_t i = size_t(y) * size_t(width) + size_t(x);
      auto r = ray_at(camera, x + 0.5, y + 0.5, width, height);
      if (r && sphere) r = seen_from_eye(*r, *sphere);
      if (!r) continue;
      const auto uv = source.to_image(r->dir);
      put_pixel(&m, i, uv.value_or(Vec2{}), r->dir, bool(uv));
    }
  });
  return m;
}

StMap inverse_stmap(const Camera& camera, const DepthSphere& sphere, const SourceProjection& source,
                    int source_width, int source_height) {
  StMap m = empty_map(source_width, source_height);
  parallel_for_each(0, source_height, [&](int y) {
    for (int x = 0; x < source_width; ++x) {
      const size_t i = size_t(y) * size_t(source_width) + size_t(x);
      const auto d = source.to_direction({(x + 0.5) / source_width, (y + 0.5) / source_height});
      if (!d) continue;
      // The sphere's point in that direction: the image positions whose rays pass through it,
      // kept only when the ray points that way (not through it backwards).
      const Vec3 p = sphere.eye + *d * sphere.depth;
      std::optional<Vec2> hit;
      for (const Vec2& uv : camera.project(p)) {
        const auto r = camera.generate(CameraSample{uv});
        if (r && dot(r->dir, normalize(p - r->org)) > 1 - 1e-6) {
          hit = uv;
          break;
        }
      }
      put_pixel(&m, i, hit.value_or(Vec2{}), *d, bool(hit));
    }
  });
  return m;
}

std::optional<SourceFootprint> source_footprint(const SourceProjection& source,
                                                const CameraRay& ray, int width, int height) {
  const auto uv = source.to_image(ray.dir);
  if (!uv) return std::nullopt;
  SourceFootprint f{*uv, {}, {}};
  // Half a pixel ahead, else half a pixel behind, doubled (three projections a pixel, not five:
  // the footprint only shapes the filter, and atan2 was a fifth of a 4K warp's time).
  const auto derivative = [&](const Vec3& step) {
    Vec2 d{};
    if (const auto plus = source.to_image(normalize(ray.dir + 0.5 * step)))
      d = *plus - *uv;
    else if (const auto minus = source.to_image(normalize(ray.dir - 0.5 * step)))
      d = *uv - *minus;
    if (source.wraps_u()) d.x -= std::round(d.x);
    return d * 2.0;
  };
  f.duv_dx = derivative(ray.ddir_du * (1.0 / width));
  f.duv_dy = derivative(ray.ddir_dv * (1.0 / height));
  return f;
}

}  // namespace anamorph
