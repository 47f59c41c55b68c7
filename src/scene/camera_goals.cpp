#include "scene/camera_goals.h"

#include <fmt/format.h>

#include "scene/scene_schema.h"

namespace anamorph {

namespace {

// The entries of the array of tables `key` of `cam` ([[camera.key]]), each with its reader.
template <class F>
void for_each_entry(const TableReader& cam, std::string_view key, F f) {
  const toml::node* n = cam.node(key);
  if (!n) return;
  const toml::array* a = n->as_array();
  if (!a || !a->is_array_of_tables())
    cam.fail(key, fmt::format("expected an array of tables ([[camera.{}]] entries)", key));
  for (size_t i = 0; i < a->size(); ++i)
    f(TableReader(*a->get(i)->as_table(), cam.full_key(fmt::format("{}[{}]", key, i))));
}

CameraConstraint read_constraint(const TableReader& r) {
  CameraConstraint c;
  c.values = r.params(constraint_schema());
  c.kind = c.values.string("kind");
  c.where = r.path();
  c.weight = c.values.number("weight");
  if (c.values.has("tolerance"))
    c.tolerance = c.values.number("tolerance");
  else if (c.kind == "keep")
    c.tolerance = c.values.number("epsilon");
  if (c.kind == "pin" || c.kind == "magnification") {
    const bool point = c.values.has("point"), object = c.values.has("object");
    if (point == object)
      r.fail(point ? "object" : "point",
             point ? "give either point or object, not both" : "is required (or object)");
  }
  return c;
}

FreeKey read_free(const TableReader& r) {
  const ParamValues v = r.params({free_schema().common});
  FreeKey f{v.string("key"), r.path(), {}, {}};
  if (!f.key.starts_with("camera."))
    r.fail("key", "only camera keys can be solved for (camera.fov, camera.coin.0.strength, ...)");
  if (v.has("min")) f.min = v.number("min");
  if (v.has("max")) f.max = v.number("max");
  if (f.min && f.max && !(*f.min < *f.max)) r.fail("max", "must be greater than min");
  return f;
}

}  // namespace

bool is_goal_key(std::string_view key) {
  return key == "constraint" || key == "free" || key == "solve";
}

CameraGoals read_camera_goals(const TableReader& cam) {
  CameraGoals g;
  for_each_entry(cam, "constraint",
                 [&](const TableReader& r) { g.constraints.push_back(read_constraint(r)); });
  for_each_entry(cam, "free", [&](const TableReader& r) { g.free.push_back(read_free(r)); });
  for (size_t i = 0; i < g.free.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (g.free[i].key == g.free[j].key)
        cam.fail(fmt::format("free[{}].key", i),
                 fmt::format("\"{}\" is already free (free[{}])", g.free[i].key, j));
  if (const toml::node* n = cam.node("solve")) {
    if (!n->is_table()) cam.fail("solve", "expected a table ([camera.solve])");
    const TableReader r(*n->as_table(), cam.full_key("solve"));
    const ParamValues v = r.params({solve_schema().common});
    g.options.loss = v.string("loss");
    g.options.loss_scale = v.number("loss_scale");
    g.options.max_iterations = int(v.integer("max_iterations"));
  }
  return g;
}

}  // namespace anamorph
