// The parameter declarations as Python data: the `anamorph` package builds its keyword
// arguments, the org/dir helper functions, their docstrings and the .pyi stubs from these, so a
// key declared in C++ appears in Python with no Python code.
#include "bindings.h"
#include "scene/declarations.h"
#include "scene/scene_schema.h"

namespace anamorph::py {

namespace {

pb::object declarations() {
  return pb::module_::import("json").attr("loads")(declarations_json().dump());
}

}  // namespace

void bind_schema(pb::module_& m) {
  m.def("declarations", &declarations,
        "Every declared parameter of presets, org/dir functions, coins and the camera, image and "
        "render tables: name, type, default (TOML text), range (None: unbounded), unit, choices "
        "and doc.");
  m.def("schema_json", &scene_json_schema, "The scene format as a JSON Schema (text).");
}

}  // namespace anamorph::py
