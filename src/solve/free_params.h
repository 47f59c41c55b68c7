// The free parameters of `anamorph solve`: each [[camera.free]] key resolved to its declaration
// (camera/presets, the camera's common keys, coins, org/dir functions), its value in the loaded
// scene (or its declared default) and its bounds (the declared range, narrowed by the entry's
// min and max). A vector or list key (camera.look_at, camera.org.points) gives one scalar per
// number; indices after it select part of it: camera.look_at.1 one number, camera.org.points.1.2
// the point in row 1, column 2 (three numbers), camera.org.points.1.2.0 its x.
#pragma once

#include <string>
#include <vector>

#include <toml++/toml.h>

#include "scene/camera_goals.h"

namespace anamorph::solve {

struct FreeValue {
  std::string key;            // the value's own key: "camera.look_at" for camera.look_at.1
  std::vector<double> start;  // the value's numbers at the start, flattened (1 for a number)
  std::vector<size_t> dims;   // its array extents: {} a number, {3} a Vec3, {rows, cols, 3} a net
};

struct FreeScalar {
  size_t value;       // index into FreeValues::values
  int component;      // into its start vector
  std::string name;   // "camera.look_at.1", "camera.fov", "camera.org.points.1.2.0", for reports
  double lo, hi;      // bounds (may be infinite)
  std::string where;  // the [[camera.free]] entry
};

// A key the free values decide: a polynomial fisheye's `camera.fov`, which the reader asks to be
// 2 theta(1) = 2 (k0 + k1 + ...) in degrees, follows its free `camera.poly` (so that a step that
// changes the coefficients is a camera, not a refused value).
struct DerivedValue {
  std::string key;  // "camera.fov"
  size_t value;     // index into FreeValues::values of the coefficients
};

struct FreeValues {
  std::vector<FreeValue> values;
  std::vector<FreeScalar> scalars;
  std::vector<DerivedValue> derived;
  std::vector<double> start() const;
  // "key=value" overrides setting every value with the scalars `x` (the shortest text that reads
  // back as the same double).
  std::vector<std::string> overrides(const std::vector<double>& x) const;
  // Each value (and each derived one) as TOML text, for the solved scene.
  std::vector<std::pair<std::string, std::string>> texts(const std::vector<double>& x) const;
};

// `scene` is the loaded scene's effective tree (includes merged, animation evaluated);
// `animated` its keys with [[animate]] entries. Throws SceneError naming the entry.
FreeValues resolve_free(const std::vector<FreeKey>& keys, const toml::table& scene,
                        const std::vector<std::string>& animated, const std::string& file);

}  // namespace anamorph::solve
