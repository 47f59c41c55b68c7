// The camera's goals for `anamorph solve` (docs/solve.md), as the scene declares them:
// [[camera.constraint]] entries (pin, size, magnification, keep), the [[camera.free]] keys the
// solver may change and the [camera.solve] options. Declared in scene/scene_schema.cpp; the
// camera reader checks them on every load (so `render` refuses a bad constraint too), the solver
// (src/solve) reads them again from the loaded scene.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "params/params.h"
#include "scene/toml_reader.h"

namespace anamorph {

struct CameraConstraint {
  std::string kind;   // "pin", "size", "magnification", "keep"
  std::string where;  // "camera.constraint[2]", for reports
  double weight = 1;
  double tolerance = 0.5;  // in the residual's unit (pixels or percent)
  ParamValues values;      // the kind's keys
};

struct FreeKey {
  std::string key;    // "camera.fov", as written
  std::string where;  // "camera.free[0]"
  std::optional<double> min, max;
};

struct SolveOptions {
  std::string loss = "huber";
  double loss_scale = 1;
  int max_iterations = 200;
};

struct CameraGoals {
  std::vector<CameraConstraint> constraints;
  std::vector<FreeKey> free;
  SolveOptions options;
};

// The camera table's keys that hold goals (each a table or array of tables): "constraint",
// "free", "solve".
bool is_goal_key(std::string_view key);

// Reads and checks them from the [camera] table `cam` (errors located, as every key's).
CameraGoals read_camera_goals(const TableReader& cam);

}  // namespace anamorph
