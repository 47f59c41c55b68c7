// The parameter declarations as Python data: the `anamorph` package builds its keyword
// arguments, the org/dir helper functions, their docstrings and the .pyi stubs from these, so a
// key declared in C++ appears in Python with no Python code.
#include "bindings.h"
#include "camera/coins.h"
#include "camera/functions.h"
#include "camera/presets.h"
#include "scene/scene_schema.h"

namespace anamorph::py {

namespace {

pb::dict spec_dict(const ParamSpec& p) {
  pb::dict d;
  d["name"] = std::string(p.name);
  d["type"] = std::string(to_string(p.type));
  const bool required = p.default_value.empty();
  const bool optional = p.default_value == "none";
  d["required"] = required;
  d["default"] = required || optional ? pb::none() : pb::cast(std::string(p.default_value));
  d["default_note"] = std::string(p.default_note);
  d["doc"] = std::string(p.doc);
  d["unit"] = std::string(p.unit);
  d["min"] = p.min;
  d["max"] = p.max;
  d["min_exclusive"] = p.min_exclusive;
  d["max_exclusive"] = p.max_exclusive;
  pb::list choices;
  for (std::string_view c : p.choices) choices.append(std::string(c));
  d["choices"] = choices;
  return d;
}

pb::list specs(std::span<const ParamSpec> ps) {
  pb::list l;
  for (const ParamSpec& p : ps) l.append(spec_dict(p));
  return l;
}

template <class Infos>
pb::dict forms(const Infos& infos) {
  pb::dict d;
  for (const auto& f : infos) {
    pb::dict e;
    e["doc"] = std::string(f.doc);
    e["params"] = specs(f.params);
    d[pb::str(std::string(f.name))] = e;
  }
  return d;
}

pb::dict declarations() {
  pb::dict d;
  d["presets"] = forms(camera_presets());
  d["org"] = forms(org_functions());
  d["dir"] = forms(dir_functions());
  d["coin"] = specs(coin_params());
  d["camera"] = specs(camera_common_params());
  d["image"] = specs(image_schema().common);
  d["render"] = specs(render_schema().common);
  return d;
}

}  // namespace

void bind_schema(pb::module_& m) {
  m.def("declarations", &declarations,
        "Every declared parameter of presets, org/dir functions, coins and the camera, image and "
        "render tables: name, type, default (TOML text), range, unit, choices and doc.");
  m.def("schema_json", &scene_json_schema, "The scene format as a JSON Schema (text).");
}

}  // namespace anamorph::py
