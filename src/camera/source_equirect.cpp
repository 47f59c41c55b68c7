// equirect source: the full sphere, longitude left to right over [-180, 180] degrees (the
// image center looks along -z), latitude from +90 at the top to -90 at the bottom; 2:1. The same
// layout as the `equirect` camera preset at its defaults, and as Blender's and most 360 footage:
//   d(u, v) = (cos(lat) sin(lon), sin(lat), -cos(lat) cos(lon)),
//   lon = 2 pi (u - 1/2), lat = pi (1/2 - v).
#include <cmath>

#include <fmt/format.h>

#include "camera/source_projection.h"
#include "params/params.h"

namespace anamorph {

namespace {

class EquirectSource final : public SourceProjection {
 public:
  std::optional<Vec2> to_image(const Vec3& d) const override {
    const double lon = std::atan2(d.x, -d.z);
    const double lat = std::asin(std::clamp(d.y, -1.0, 1.0));
    return Vec2{lon / (2 * kPi) + 0.5, 0.5 - lat / kPi};
  }
  std::optional<Vec3> to_direction(Vec2 uv) const override {
    const double lon = 2 * kPi * (uv.x - 0.5), lat = kPi * (0.5 - uv.y);
    return Vec3{std::cos(lat) * std::sin(lon), std::sin(lat), -std::cos(lat) * std::cos(lon)};
  }
  bool wraps_u() const override { return true; }
  double aspect() const override { return 2; }
  std::string describe() const override { return "equirect"; }
};

std::unique_ptr<SourceProjection> create(std::span<const std::string> args, double) {
  if (!args.empty())
    throw ParamError("--source", "--source equirect takes no arguments (it is the full sphere)");
  return std::make_unique<EquirectSource>();
}

}  // namespace

const SourceProjectionInfo kEquirectSource{
    "equirect", "equirect",
    "Full-sphere latitude/longitude image, 2:1, center looking along -z (the equirect preset).",
    create};

}  // namespace anamorph
