// Source projections: how an image made elsewhere (an equirectangular render, fisheye footage, a
// cubemap, a perspective plate) lays out directions, so that `anamorph stmap` can tell for each
// pixel of a camera where to fetch it and `anamorph warp` can reproject the image.
//
// A source looks from the world origin's frame: x right, y up, looking along -z (the camera
// space of every preset with its default look_at), so that an equirect source is exactly the
// image an `equirect` camera at the default orientation renders. Image positions are the camera
// contract's (u, v) in [0,1]^2: u left to right, v top to bottom, pixel centers at (x + 0.5)/W.
//
// Kinds are registered by name (source_projections.cpp, one file each) and named on the command
// line as KIND[:ARG[:ARG]], e.g. "equirect", "cubemap:6x1", "fisheye:180", "perspective:90:1.5".
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "math/vec.h"

namespace anamorph {

class SourceProjection {
 public:
  virtual ~SourceProjection() = default;
  // The image position that shows the unit direction `d`, or none (outside a fisheye's circle,
  // behind a perspective plate). Must be const and thread-safe.
  virtual std::optional<Vec2> to_image(const Vec3& d) const = 0;
  // The unit direction shown at image position uv, or none.
  virtual std::optional<Vec3> to_direction(Vec2 uv) const = 0;
  // Whether u wraps around (the equirect's seam): filters fetch across u = 0 / u = 1.
  virtual bool wraps_u() const { return false; }
  // The image aspect (width / height) the projection is made for, checked against an input.
  virtual double aspect() const = 0;
  virtual std::string describe() const = 0;
};

// create() gets the spec's arguments after the kind's name ("fisheye:180:1.5" gives {"180",
// "1.5"}) and the aspect of the image at hand (width / height), the default of kinds that take one.
struct SourceProjectionInfo {
  std::string_view name;
  std::string_view usage;  // e.g. "fisheye:FOV[:ASPECT]"
  std::string_view doc;
  std::unique_ptr<SourceProjection> (*create)(std::span<const std::string> args, double aspect);
};

extern const SourceProjectionInfo kEquirectSource, kCubemapSource, kFisheyeSource,
    kPerspectiveSource;

std::span<const SourceProjectionInfo* const> source_projections();

// Parses "KIND[:ARG...]"; `aspect` is the image's (width / height), for kinds whose ASPECT
// argument is left out. Throws ParamError (key "--source") naming the valid kinds or what is
// wrong with an argument.
std::unique_ptr<SourceProjection> make_source_projection(std::string_view spec, double aspect = 1);

// A number argument of a spec (for the kinds): finite, in [lo, hi], or ParamError naming `what`.
double source_number(const std::string& text, std::string_view what, double lo, double hi);

// The arguments FOV[:ASPECT] of kind `kind` (fisheye, perspective): FOV in degrees within
// (0, max_fov], ASPECT the image's when left out; ParamError with an example otherwise.
struct FovAspect {
  double fov, aspect;
};
FovAspect source_fov_aspect(std::span<const std::string> args, std::string_view kind,
                            double max_fov, double example_fov, double image_aspect);

}  // namespace anamorph
