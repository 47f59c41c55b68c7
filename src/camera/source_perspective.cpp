// perspective source: a pinhole plate looking along -z, "perspective:FOV[:ASPECT]" (FOV degrees
// across the width, in (0, 180); ASPECT = width / height, by default the image's (1 for an STMap
// without --source-size)): the `perspective` preset with its horizontal fov. With tx = tan(FOV /
// 2), ty = tx / ASPECT:
//   d = normalize((2u - 1) tx, (1 - 2v) ty, -1); none behind the plate or outside it.
#include <cmath>
#include <cstdio>

#include "camera/source_projection.h"
#include "params/params.h"

namespace anamorph {

namespace {

class PerspectiveSource final : public SourceProjection {
 public:
  PerspectiveSource(double fov_deg, double aspect)
      : fov_(fov_deg), aspect_(aspect), tx_(std::tan(radians(fov_deg) / 2)), ty_(tx_ / aspect) {}
  std::optional<Vec2> to_image(const Vec3& d) const override {
    if (!(d.z < 0)) return std::nullopt;
    const Vec2 uv{0.5 * (d.x / (-d.z * tx_) + 1), 0.5 * (1 - d.y / (-d.z * ty_))};
    constexpr double tol = 1e-12;
    if (!(uv.x >= -tol && uv.x <= 1 + tol && uv.y >= -tol && uv.y <= 1 + tol)) return std::nullopt;
    return uv;
  }
  std::optional<Vec3> to_direction(Vec2 uv) const override {
    return normalize(Vec3{(2 * uv.x - 1) * tx_, (1 - 2 * uv.y) * ty_, -1});
  }
  double aspect() const override { return aspect_; }
  std::string describe() const override {
    char buf[64];
    std::snprintf(buf, sizeof buf, "perspective:%g:%g", fov_, aspect_);
    return buf;
  }

 private:
  double fov_, aspect_, tx_, ty_;
};

std::unique_ptr<SourceProjection> create(std::span<const std::string> args, double image_aspect) {
  const FovAspect fa = source_fov_aspect(args, "perspective", 179.9, 90, image_aspect);
  return std::make_unique<PerspectiveSource>(fa.fov, fa.aspect);
}

}  // namespace

const SourceProjectionInfo kPerspectiveSource{
    "perspective", "perspective:FOV[:ASPECT]",
    "Pinhole plate looking along -z, FOV degrees across the width (the perspective preset).",
    create};

}  // namespace anamorph
