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

StMap forward_stmap(const Camera& camera, const SourceProjection& source, int width, int height) {
  StMap m = empty_map(width, height);
  parallel_for_each(0, height, [&](int y) {
    for (int x = 0; x < width; ++x) {
      const size_t i = size_t(y) * size_t(width) + size_t(x);
      const auto r = ray_at(camera, x + 0.5, y + 0.5, width, height);
      if (!r) continue;
      const auto uv = source.to_image(r->dir);
      put_pixel(&m, i, uv.value_or(Vec2{}), r->dir, bool(uv));
    }
  });
  return m;
}

StMap inverse_stmap(const Camera& camera, const Vec3& origin, const SourceProjection& source,
                    int source_width, int source_height) {
  StMap m = empty_map(source_width, source_height);
  parallel_for_each(0, source_height, [&](int y) {
    for (int x = 0; x < source_width; ++x) {
      const size_t i = size_t(y) * size_t(source_width) + size_t(x);
      const auto d = source.to_direction({(x + 0.5) / source_width, (y + 0.5) / source_height});
      if (!d) continue;
      // A point one unit along the direction: the image positions whose rays pass through it,
      // kept only when the ray points that way (not through it backwards).
      std::optional<Vec2> hit;
      for (const Vec2& uv : camera.project(origin + *d)) {
        const auto r = camera.generate(CameraSample{uv});
        if (r && dot(r->dir, *d) > 1 - 1e-6) {
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
