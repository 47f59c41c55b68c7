// Camera.solve: the camera's goals solved by src/solve (the library behind `anamorph solve`,
// docs/solve.md) on the scene text the Python front end writes; the solved camera is the same
// text with the solved values as overrides.
#include "bindings.h"
#include "camera_handle.h"
#include "solve/camera_solve.h"

namespace anamorph::py {

namespace {

pb::dict solve_text(const std::string& text, const std::string& name) {
  SceneSource source;
  source.text = text;
  source.name = name;
  const auto scene = std::make_shared<const Scene>(source.load());
  solve::SolveInput in;
  in.text = text;
  in.file = name;
  in.loaded = scene.get();
  const solve::SolveReport r = solve::solve_camera(in);
  pb::list values, constraints;
  for (const solve::ValueReport& v : r.values)
    values.append(pb::dict(pb::arg("name") = v.name, pb::arg("start") = v.start,
                           pb::arg("value") = v.value, pb::arg("min") = v.lo, pb::arg("max") = v.hi,
                           pb::arg("at_bound") = v.at_bound));
  for (const solve::ConstraintReport& c : r.constraints)
    constraints.append(pb::dict(
        pb::arg("where") = c.where, pb::arg("kind") = c.kind, pb::arg("residual") = c.residual,
        pb::arg("unit") = c.unit, pb::arg("tolerance") = c.tolerance, pb::arg("met") = c.met,
        pb::arg("met_alone") = c.met_alone, pb::arg("conflicts") = c.conflicts));
  SceneSource solved = source;
  for (const auto& [key, value] : r.texts) solved.overrides.push_back(key + "=" + value);
  auto camera = std::make_shared<const Scene>(solved.load());
  return pb::dict(pb::arg("camera") = CameraHandle(solved, std::move(camera), nullptr),
                  pb::arg("values") = values, pb::arg("constraints") = constraints,
                  pb::arg("iterations") = r.iterations, pb::arg("termination") = r.termination,
                  pb::arg("met") = r.all_met());
}

}  // namespace

void bind_solve(pb::module_& m) {
  m.def("solve_text", &solve_text, pb::arg("text"), pb::arg("name"),
        "Solves the [[camera.free]] keys of the scene `text` for its [[camera.constraint]] "
        "entries (docs/solve.md).");
}

}  // namespace anamorph::py
