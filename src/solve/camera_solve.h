// `anamorph solve`: the camera's free keys solved for its constraints (docs/solve.md) with Ceres
// (Levenberg-Marquardt, a robust loss per constraint, bounds from the declarations; derivatives by
// the chain rule through the image positions of the constraints' points and the implicit function
// theorem, not by differences of the inverse map `project`, except magnification's: docs/solve.md).
// Each evaluation builds the camera through the scene reader (load_view with the free values as
// overrides), so every check and default is the reader's. Deterministic: one thread, no random
// numbers. This library is the only one that links Ceres.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "scene/scene.h"

namespace anamorph::solve {

struct ValueReport {
  std::string name;  // "camera.fov", "camera.look_at.1"
  double start = 0, value = 0, lo = 0, hi = 0;
  bool at_bound = false;  // the solution lies on lo or hi
};

struct ConstraintReport {
  std::string where;  // "camera.constraint[0]"
  std::string kind;
  std::string unit;     // "px" or "%"
  double residual = 0;  // +inf: the camera does not see its point
  double tolerance = 0;
  bool met = false;
  // When not met: met alone from the start (then `conflicts` names the constraints it cannot be
  // met together with), or not even alone (the free keys, within their bounds, cannot reach it).
  bool met_alone = false;
  std::vector<std::string> conflicts;
};

struct SolveReport {
  std::vector<ValueReport> values;
  std::vector<ConstraintReport> constraints;
  // The solved values as TOML text by key, for the scene's text ("camera.look_at", "[1, 2, 3]").
  std::vector<std::pair<std::string, std::string>> texts;
  int iterations = 0;
  std::string termination;  // Ceres' message
  bool all_met() const;
};

struct SolveInput {
  std::string text;  // the scene file's text
  std::filesystem::path file;
  std::vector<std::string> overrides;  // --set etc., as the scene was loaded with
  const Scene* loaded = nullptr;       // the scene loaded from them (objects, model cameras)
  double frame = 0;                    // the frame `loaded` was loaded at
  // Where `gltf_camera`'s model cameras come from when not `loaded` (a scene of the view alone,
  // as the editor loads it).
  const Scene* models = nullptr;
  // Where the solve starts, one number per free scalar (`solve --frames`: the previous frame's
  // solution); empty: the scene's own values.
  std::vector<double> start;
  // Whether constraints not met are solved again alone and in pairs to name conflicts (the
  // editor's live pins skip it: a drag asks again at once).
  bool explain = true;
  // At most this many iterations when > 0 (else [camera.solve]'s).
  int max_iterations = 0;
};

// Throws SceneError for goals that cannot be solved as given (no constraint or free key, a key
// that is not a number of the camera, an unknown object).
SolveReport solve_camera(const SolveInput& in);

}  // namespace anamorph::solve
