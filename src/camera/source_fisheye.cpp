// fisheye source: an equidistant fisheye looking along -z, "fisheye:FOV[:ASPECT]" (FOV degrees
// across the image circle, in (0, 360]; ASPECT = width / height, by default the image's (1 for an
// STMap without --source-size)). The circle's diameter is the shorter image side, centered: the
// `fisheye` preset with mapping = "equidistant" and fit = "circle". With a = (u - 1/2) sa, b = (1/2
// - v) sb scaled so that the circle has radius 1, r = |(a, b)|, theta = r FOV / 2:
//   d = (sin(theta) a / r, sin(theta) b / r, -cos(theta)); none outside the circle.
#include <cmath>
#include <cstdio>

#include "camera/source_projection.h"
#include "params/params.h"

namespace anamorph {

namespace {

class FisheyeSource final : public SourceProjection {
 public:
  FisheyeSource(double fov_deg, double aspect)
      : fov_(fov_deg), half_(radians(fov_deg) / 2), aspect_(aspect) {
    sa_ = 2 * std::max(aspect, 1.0);
    sb_ = 2 * std::max(1 / aspect, 1.0);
  }
  std::optional<Vec2> to_image(const Vec3& d) const override {
    const double rho = std::hypot(d.x, d.y);
    const double theta = std::atan2(rho, -d.z);
    if (theta > half_ * (1 + 1e-12)) return std::nullopt;
    const double r = theta / half_;
    const double a = rho > 0 ? r * d.x / rho : 0, b = rho > 0 ? r * d.y / rho : 0;
    return Vec2{0.5 + a / sa_, 0.5 - b / sb_};
  }
  std::optional<Vec3> to_direction(Vec2 uv) const override {
    const double a = (uv.x - 0.5) * sa_, b = (0.5 - uv.y) * sb_;
    const double r = std::hypot(a, b);
    if (!(r <= 1)) return std::nullopt;
    const double theta = r * half_;
    const double s = r > 0 ? std::sin(theta) / r : 0;
    return Vec3{s * a, s * b, -std::cos(theta)};
  }
  double aspect() const override { return aspect_; }
  std::string describe() const override {
    char buf[64];
    std::snprintf(buf, sizeof buf, "fisheye:%g:%g", fov_, aspect_);
    return buf;
  }

 private:
  double fov_, half_, aspect_, sa_ = 2, sb_ = 2;
};

std::unique_ptr<SourceProjection> create(std::span<const std::string> args, double image_aspect) {
  const FovAspect fa = source_fov_aspect(args, "fisheye", 360, 180, image_aspect);
  return std::make_unique<FisheyeSource>(fa.fov, fa.aspect);
}

}  // namespace

const SourceProjectionInfo kFisheyeSource{
    "fisheye", "fisheye:FOV[:ASPECT]",
    "Equidistant fisheye looking along -z, FOV degrees across the image circle (the shorter "
    "side), as the fisheye preset with fit = \"circle\".",
    create};

}  // namespace anamorph
