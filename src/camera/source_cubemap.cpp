// cubemap source: six 90-degree faces, the layout and face orientations of the `cubemap` camera
// preset (camera/cube_faces.h): "cubemap[:3x2|6x1[:inside|opengl]]", 3x2 and inside by default.
#include <cmath>

#include "camera/cube_faces.h"
#include "camera/source_projection.h"
#include "params/params.h"

namespace anamorph {

namespace {

class CubemapSource final : public SourceProjection {
 public:
  CubemapSource(const CubeFaceTable& faces, int cols, int rows, std::string name)
      : faces_(faces), cols_(cols), rows_(rows), name_(std::move(name)) {}
  std::optional<Vec2> to_image(const Vec3& d) const override {
    return cube_layout_position(faces_, cols_, rows_, d);
  }
  std::optional<Vec3> to_direction(Vec2 uv) const override {
    if (!(uv.x >= 0 && uv.x <= 1 && uv.y >= 0 && uv.y <= 1)) return std::nullopt;
    const int col = std::min(int(uv.x * cols_), cols_ - 1),
              row = std::min(int(uv.y * rows_), rows_ - 1);
    const double s = uv.x * cols_ - col, t = uv.y * rows_ - row;
    const CubeFace& f = faces_[size_t(row * cols_ + col)];
    return normalize(f.axis + f.right * (2 * s - 1) + f.down * (2 * t - 1));
  }
  double aspect() const override { return double(cols_) / rows_; }
  std::string describe() const override { return name_; }

 private:
  const CubeFaceTable& faces_;
  int cols_, rows_;
  std::string name_;
};

std::unique_ptr<SourceProjection> create(std::span<const std::string> args, double) {
  if (args.size() > 2)
    throw ParamError("--source", "--source cubemap takes at most a layout and a convention");
  const std::string layout = args.empty() ? "3x2" : args[0];
  const std::string convention = args.size() < 2 ? "inside" : args[1];
  if (layout != "3x2" && layout != "6x1")
    throw ParamError("--source", "--source cubemap: layout \"" + layout + "\" is not 3x2 or 6x1");
  if (convention != "inside" && convention != "opengl")
    throw ParamError("--source",
                     "--source cubemap: convention \"" + convention + "\" is not inside or opengl");
  return std::make_unique<CubemapSource>(convention == "opengl" ? kCubeOpenGl : kCubeInside,
                                         layout == "6x1" ? 6 : 3, layout == "6x1" ? 1 : 2,
                                         "cubemap:" + layout + ":" + convention);
}

}  // namespace

const SourceProjectionInfo kCubemapSource{
    "cubemap", "cubemap[:3x2|6x1[:inside|opengl]]",
    "Six 90-degree faces +X -X +Y -Y +Z -Z, as the cubemap preset lays them out.", create};

}  // namespace anamorph
