#include "bindings.h"

PYBIND11_MODULE(_anamorph, m) {
  m.doc() = "anamorph's C++ core; use the `anamorph` package, which wraps it.";
  m.attr("__version__") = ANAMORPH_VERSION;
  anamorph::py::bind_errors(m);
  anamorph::py::bind_schema(m);
  anamorph::py::bind_camera(m);
  anamorph::py::bind_scene(m);
  anamorph::py::bind_image(m);
  anamorph::py::bind_warp(m);
  anamorph::py::bind_solve(m);
}
