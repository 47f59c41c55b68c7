#include "scene/scene_loader.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>
#include <span>

#include "io/image_io.h"
#include "material/material_kinds.h"
#include "math/frame.h"
#include "math/input_limits.h"
#include "math/user_text.h"
#include "params/toml_parse.h"
#include "scene/animation.h"
#include "scene/camera_reader.h"
#include "scene/gltf_lights.h"
#include "scene/gltf_scene.h"
#include "scene/load_common.h"
#include "scene/loaders.h"
#include "scene/scene_pose.h"
#include "scene/toml_edit.h"
#include "scene/toml_reader.h"
#include "scene/world_extent.h"

namespace anamorph {

namespace fs = std::filesystem;

namespace {

// A camera that gives no ray anywhere (a direction expression of 1/0, an origin surface that is
// never defined) renders a transparent image without complaint: say so at load.
void warn_if_no_rays(const Camera& cam, std::vector<std::string>* warnings) {
  constexpr int n = 17;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      CameraSample cs;
      cs.uv = {(i + 0.5) / n, (j + 0.5) / n};
      if (cam.generate(cs)) return;
    }
  warnings->push_back(fmt::format(
      "camera: gives no ray at any of {} image positions tried (origins or directions that are "
      "never finite, or vanish, or origins beyond the {:g} scene units from the origin rays may "
      "start at); the image will be transparent",
      n * n, kMaxCoordinate));
}

// ---- includes and overrides -------------------------------------------------------------------

toml::table parse_toml_file(const fs::path& file) {
  // Read here, not by toml++: it reads a directory as an empty scene and reports a file it
  // cannot open as a syntax error.
  std::string text;
  try {
    text = read_text_file(file);
  } catch (const LoadError& e) {
    throw SceneError({file.string()}, "", e.what());
  }
  try {
    return parse_toml(text, file.string());
  } catch (const toml::parse_error& e) {
    SourceLoc l;
    l.file = file.string();
    l.line = int(e.source().begin.line);
    l.column = int(e.source().begin.column);
    throw SceneError(l, "", fmt::format("TOML syntax error: {}", e.description()));
  }
}

// Tables merge key by key, arrays of tables concatenate (base first), other values: `over` wins.
// Nodes are moved, not copied: a moved node keeps its source (file, line, column), so an error in
// an included file names that file (toml++ copies drop it).
void merge_into(toml::table& base, toml::table&& over) {
  for (auto&& [k, v] : over) {
    toml::node* b = base.get(k.str());
    if (b && b->is_table() && v.is_table()) {
      merge_into(*b->as_table(), std::move(*v.as_table()));
    } else if (b && b->is_array_of_tables() && v.is_array_of_tables()) {
      for (auto& e : *v.as_array()) b->as_array()->push_back(std::move(e));
    } else {
      base.insert_or_assign(k, std::move(v));
    }
  }
}

// Makes every relative `file = "..."` in an included tree absolute, against the included file's
// directory: merging copies nodes, and copies do not keep their source file.
void anchor_paths(toml::node& n, const fs::path& dir) {
  if (toml::table* t = n.as_table()) {
    for (auto&& [k, v] : *t) {
      if (k.str() == "file" && v.is_string()) {
        const fs::path p = *v.value<std::string>();
        if (p.is_relative())
          v.as_string()->get() = fs::absolute(dir / p).lexically_normal().string();
      } else {
        anchor_paths(v, dir);
      }
    }
  } else if (toml::array* a = n.as_array()) {
    for (auto& e : *a) anchor_paths(e, dir);
  }
}

// Bounds on the include tree: a cycle, or a fan-out of a few includes per level over a dozen
// levels (millions of reads from a 1 KB file), stops with an error instead of hanging.
constexpr int kMaxIncludeDepth = 16;
constexpr int kMaxIncludedFiles = 1000;

toml::table load_with_includes(const fs::path& file, int depth, int* files_read);

// `t`, read from `file`, with its `include`s merged in (their entries first).
toml::table merge_includes(toml::table t, const fs::path& file, int depth, int* files_read) {
  const toml::node* inc = t.get("include");
  if (!inc) return t;
  std::vector<std::string> files;
  TableReader r(t, "");
  if (inc->is_string())
    files.push_back(*inc->value<std::string>());
  else if (const toml::array* a = inc->as_array()) {
    for (const auto& e : *a) {
      if (!e.is_string()) r.fail("include", "expected a file name or a list of file names");
      files.push_back(*e.value<std::string>());
    }
  } else {
    r.fail("include", "expected a file name or a list of file names");
  }
  toml::table merged;
  for (const auto& f : files) {
    if (has_nul(f)) r.fail("include", nul_in_path_message(f));
    const fs::path p = file.parent_path() / f;
    if (!fs::exists(p)) r.fail("include", fmt::format("included file not found: {}", p.string()));
    const ReadRole role("a file the scene includes");
    toml::table inc_table = load_with_includes(p, depth + 1, files_read);
    anchor_paths(inc_table, p.parent_path());
    merge_into(merged, std::move(inc_table));
  }
  t.erase("include");
  merge_into(merged, std::move(t));
  return merged;
}

toml::table load_with_includes(const fs::path& file, int depth, int* files_read) {
  if (depth > kMaxIncludeDepth)
    throw SceneError({file.string()}, "include", "includes nested too deeply (a cycle?)");
  if (++*files_read > kMaxIncludedFiles)
    throw SceneError({file.string()}, "include",
                     fmt::format("more than {} files included in all (a cycle, or includes that "
                                 "fan out level after level?)",
                                 kMaxIncludedFiles));
  return merge_includes(parse_toml_file(file), file, depth, files_read);
}

toml::table load_with_includes(const fs::path& file) {
  // A glTF file is a scene of its own (gltf_scene.h): its defaults, the file as its object.
  if (is_gltf_scene_file(file)) return gltf_scene_table(file);
  const ReadRole role("the scene file");
  int files_read = 0;
  return load_with_includes(file, 0, &files_read);
}

void apply_override(toml::table& root, const std::string& kv) {
  const size_t eq = kv.find('=');
  if (eq == std::string::npos || eq == 0)
    throw SceneError({}, kv, "expected --set KEY=VALUE (e.g. --set camera.fov=90)");
  const toml::table value = parse_value_text(kv.substr(eq + 1), kv.substr(0, eq));
  set_path(root, kv.substr(0, eq), *value.get("v"), {});
}

// ---- materials and textures -------------------------------------------------------------------

struct Context {
  fs::path dir;  // relative paths resolve against the scene file's directory
  Scene* scene;
  std::map<std::string, uint32_t> material_ids;
  // Where each [[material]]'s name is written (for an override that names two glTF materials).
  std::map<std::string, std::pair<SourceLoc, std::string>> material_sites;
  // Only checking the keys (check_scene_frame): models and images are not read (their files
  // must exist, as always).
  bool check_only = false;
};

Wrap wrap_of(const std::string& w) {
  return w == "clamp" ? Wrap::Clamp : (w == "mirror" ? Wrap::Mirror : Wrap::Repeat);
}

// The texture (or constant colour) of parameter `key` of r's table.
Texture read_texture(const TableReader& r, const ParamValues& v, std::string_view key, bool srgb,
                     bool check_only) {
  if (!v.is_table(key)) return Texture::constant(v.color(key));
  const std::string type = v.function(key).type;
  const ParamValues& t = v.function(key).values;
  Texture tex;
  if (type == "image") {
    tex.kind = Texture::Kind::Image;
    const ReadRole role("a texture");
    try {
      if (!check_only) tex.image = std::make_shared<MipMap>(read_image(t.string("file"), srgb));
    } catch (const std::exception& e) {
      r.fail_at(*r.node(key)->as_table()->get("file"), std::string(key) + ".file", e.what());
    }
    tex.value = t.color("scale_color");
    tex.wrap_s = tex.wrap_t = wrap_of(t.string("wrap"));
    tex.nearest = t.boolean("nearest");
    const Vec3 off = t.vec3("uv_offset"), sc = t.vec3("uv_scale");
    tex.uv_transform = UvTransform::from_offset_rotation_scale(
        {off.x, off.y}, radians(t.number("uv_rotation")), {sc.x, sc.y});
    return tex;
  }
  tex.kind = type == "checker" ? Texture::Kind::Checker : Texture::Kind::Grid;
  const std::string s = t.has("space") ? t.string("space") : type == "checker" ? "world" : "uv";
  tex.space = s == "uv" ? Texture::Space::Uv
                        : (s == "object" ? Texture::Space::Object : Texture::Space::World);
  tex.color_a = t.color("color_a");
  tex.color_b = t.color("color_b");
  tex.scale = t.number("scale");
  tex.line_width = t.number("line_width");
  if (t.has("transform")) tex.pattern_from_space = t.transform("transform").inverse();
  return tex;
}

// A [[material]]: its kind (`type`) makes it from the declared keys (material/material_kinds.h).
std::unique_ptr<Material> read_material(const TableReader& r, bool check_only) {
  const ParamValues v = r.params(material_schema());
  try {
    return make_material(v, [&](std::string_view key, bool srgb) {
      return read_texture(r, v, key, srgb, check_only);
    });
  } catch (const ParamError& e) {
    r.fail(e.key, e.message());
  }
}

uint32_t material_ref(Context& c, const TableReader& r, const ParamValues& v,
                      std::string_view key) {
  if (!v.has(key)) return 0;  // the default material
  const std::string& name = v.string(key);
  auto it = c.material_ids.find(name);
  if (it == c.material_ids.end()) {
    std::vector<std::string> names;
    for (const auto& [n, _] : c.material_ids) names.push_back(n);
    const std::string s = suggest(name, names);
    r.fail(key, fmt::format("no material named \"{}\"{}", name,
                            s.empty() ? "" : fmt::format(" (did you mean \"{}\"?)", s)));
  }
  return it->second;
}

// Rotation taking +y to unit n (orientation preserving): x -> t, y -> n, z -> s of n's frame.
Transform y_to(const Vec3& n) {
  const Frame f = Frame::from_normal(normalize(n));
  Mat4 m = Mat4::identity();
  for (int k = 0; k < 3; ++k) {
    m.m[k][0] = f.t[k];
    m.m[k][1] = f.n[k];
    m.m[k][2] = f.s[k];
  }
  return {m, transpose(m)};
}

Transform transform_or_identity(const ParamValues& v, std::string_view key) {
  return v.has(key) ? v.transform(key) : Transform();
}

// A model's cameras and lights (unless the object drops them) and its rig (glTF): what moves
// is marked so, and the rig remembers where its parts went in the scene.
void add_model_rig(Scene& s, const ParamValues& v, LoadedModel& m, const Transform& xf,
                   uint32_t proto_base, uint32_t inst_base) {
  SceneRig rig;
  rig.world_from_model = xf;
  rig.first_instance = inst_base;
  rig.first_prototype = proto_base;
  if (v.boolean("cameras")) {
    rig.first_camera = int(s.model_cameras.size());
    for (auto& cam : m.cameras) {
      cam.world_from_camera = xf * cam.world_from_camera;
      s.model_cameras.push_back(cam);
    }
  }
  if (v.boolean("lights")) {
    rig.first_light = int(s.lights.size());
    const bool cycles = v.string("spot_falloff") == "cycles";
    for (const ModelLight& l : m.lights)
      s.lights.push_back(scene_light(l, xf * l.world_from_light, cycles));
  }
  if (!m.rig) return;
  rig.rig = m.rig;
  rig.animate = v.boolean("animation") && m.rig->animated();
  s.rigs.push_back(std::move(rig));
}

// The scene's index of each of a model's materials: a [[material]] of the same name replaces it
// (docs/gltf.md, precedence); the others join the scene. A [[material]] whose name two of the
// model's materials share is ambiguous: an error at its name.
std::vector<uint32_t> model_material_ids(Context& c, const ParamValues& v,
                                         MaterialList& materials) {
  Scene& s = *c.scene;
  std::vector<uint32_t> ids;
  std::map<std::string, size_t> first;  // of the overridden names: the model's first index
  for (size_t i = 0; i < materials.size(); ++i) {
    const std::string& name = materials[i]->name;
    const auto it = c.material_ids.find(name);
    if (it == c.material_ids.end()) {
      ids.push_back(uint32_t(s.materials.size()));
      s.materials.push_back(std::move(materials[i]));
      continue;
    }
    if (const auto [at, fresh] = first.emplace(name, i); !fresh) {
      const auto& [loc, key] = c.material_sites.at(name);
      throw SceneError(loc, key,
                       fmt::format("\"{}\" names more than one material of {} (materials {} "
                                   "and {}): the override is ambiguous; rename one in the file",
                                   name, v.string("file"), at->second, i));
    }
    ids.push_back(it->second);
  }
  return ids;
}

// What place_objects needs to move a model's object later: where its instances sit in it.
void record_placement(Scene& s, const ParamValues& v, const LoadedModel& m, const Transform& xf,
                      int table, uint32_t inst_base) {
  PlacedObject p;
  p.table = table;
  p.transform = xf;
  p.first_instance = inst_base;
  for (const Instance& inst : m.instances) p.model_from_object.push_back(inst.world_from_object);
  p.rig = m.rig ? int(s.rigs.size()) : -1;  // (add_model_rig adds it next)
  p.moves_others =
      (v.boolean("lights") && !m.lights.empty()) || (v.boolean("cameras") && !m.cameras.empty());
  s.placed_objects.push_back(std::move(p));
}

void add_model(Context& c, const TableReader& r, const ParamValues& v, const std::string& name,
               const Transform& xf, int table) {
  Scene& s = *c.scene;
  if (c.check_only) {
    material_ref(c, r, v, "material");
    return;
  }
  LoadedModel m;
  const ReadRole role("a model");
  try {
    m = load_model(v.string("file"));
  } catch (const std::exception& e) {
    r.fail_at(*r.node("file"), "file", e.what());
  }
  const bool override_mat = v.has("material");
  const uint32_t mat = material_ref(c, r, v, "material");
  const std::vector<uint32_t> mat_ids =
      override_mat ? std::vector<uint32_t>{} : model_material_ids(c, v, m.materials);
  const auto proto_base = uint32_t(s.prototypes.size());
  const auto inst_base = uint32_t(s.instances.size());
  for (auto& pr : m.prototypes) {
    for (auto& mesh : pr.meshes) mesh.material = override_mat ? mat : mat_ids[mesh.material];
    s.prototypes.push_back(std::move(pr));
  }
  std::vector<Bounds3> boxes;  // of the model's prototypes, in their own space
  for (const Prototype& pr : std::span(s.prototypes).subspan(proto_base))
    boxes.push_back(prototype_bounds(pr));
  record_placement(s, v, m, xf, table, inst_base);
  for (auto& inst : m.instances) {
    const std::string e = placement_error(xf * inst.world_from_object, boxes[inst.prototype]);
    if (!e.empty())
      r.fail(v.has("transform") ? "transform" : "file",
             inst.name.empty() ? e : fmt::format("node \"{}\": {}", inst.name, e));
    inst.prototype += proto_base;
    inst.world_from_object = xf * inst.world_from_object;
    inst.name = name + (inst.name.empty() ? "" : "/" + inst.name);
    s.instances.push_back(std::move(inst));
  }
  add_model_rig(s, v, m, xf, proto_base, inst_base);
  for (auto& w : m.warnings) s.warnings.push_back(w);
  for (auto& l : m.summary) s.model_summaries.push_back(std::move(l));
}

// Where an analytic shape sits, from its type's keys (validated beyond their ranges here).
void place_shape(const TableReader& r, const ParamValues& v, const std::string& type,
                 const Transform& xf, AnalyticShape& sh) {
  const auto nonzero = [&](const char* key) {
    const Vec3 n = v.vec3(key);
    if (!(length(n) > 0)) r.fail(key, "must not be zero");
    return n;
  };
  if (type == "sphere") {
    sh.kind = AnalyticShape::Kind::Sphere;
    sh.radius = v.number("radius");
    sh.world_from_object = xf * Transform::translate(v.vec3("center"));
  } else if (type == "plane") {
    sh.kind = AnalyticShape::Kind::Plane;
    const Vec3 n = nonzero("normal");
    sh.world_from_object = xf * Transform::translate(v.vec3("point")) * y_to(n);
  } else if (type == "box") {
    sh.kind = AnalyticShape::Kind::Box;
    Vec3 center = v.vec3("center"), size = v.vec3("size");
    if (v.has("min") || v.has("max")) {
      const Vec3 lo = v.has("min") ? v.vec3("min") : Vec3{-0.5, -0.5, -0.5};
      const Vec3 hi = v.has("max") ? v.vec3("max") : Vec3{0.5, 0.5, 0.5};
      center = (lo + hi) * 0.5;
      size = hi - lo;
      if (min_component(size) <= 0)
        r.fail("max", "max must be greater than min in every component");
    } else if (min_component(size) <= 0) {
      r.fail("size", "every component must be > 0");
    }
    sh.size = size;
    sh.world_from_object = xf * Transform::translate(center);
  } else if (type == "cylinder") {
    sh.kind = AnalyticShape::Kind::Cylinder;
    const Vec3 base = v.vec3("base"), top = v.vec3("top");
    sh.height = length(top - base);
    if (!(sh.height > 0)) r.fail("top", "top must differ from base");
    sh.radius = v.number("radius");
    sh.capped = v.boolean("capped");
    sh.world_from_object = xf * Transform::translate(base) * y_to(top - base);
  } else if (type == "rectangle") {
    // Object space is the unit square in y = 0; x -> edge_v, y -> the unit normal, z -> edge_u
    // keeps the orientation (determinant > 0) with the normal along edge_u x edge_v.
    sh.kind = AnalyticShape::Kind::Rectangle;
    const Vec3 eu = v.vec3("edge_u"), ev = v.vec3("edge_v"), n = cross(eu, ev);
    if (!(length(n) > 1e-12 * length(eu) * length(ev)))
      r.fail("edge_v", "edge_u and edge_v must not be parallel (or zero)");
    Mat4 m = Mat4::identity();
    const Vec3 un = normalize(n);
    for (int k = 0; k < 3; ++k) m.m[k][0] = ev[k], m.m[k][1] = un[k], m.m[k][2] = eu[k];
    sh.world_from_object = xf * Transform::translate(v.vec3("center")) * Transform(m);
  } else {  // disk
    sh.kind = AnalyticShape::Kind::Disk;
    const Vec3 n = nonzero("normal");
    sh.radius = v.number("radius");
    sh.world_from_object = xf * Transform::translate(v.vec3("center")) * y_to(n);
  }
}

void read_object(Context& c, const TableReader& r, int index) {
  const ParamValues v = r.params(object_schema());
  const std::string type = v.string("type");
  const std::string name = v.has("name") ? v.string("name") : fmt::format("{}{}", type, index);
  const Transform xf = transform_or_identity(v, "transform");
  if (type == "mesh") {
    add_model(c, r, v, name, xf, index);
    return;
  }
  AnalyticShape sh;
  sh.name = name;
  sh.material = material_ref(c, r, v, "material");
  place_shape(r, v, type, xf, sh);
  if (const std::string e = placement_error(sh.world_from_object, shape_object_bounds(sh));
      !e.empty()) {
    // (Each key is within the world alone: the sum of a position and a size, or a transform,
    // takes the shape beyond it.)
    const char* size_key = type == "sphere" || type == "disk" ? "radius"
                           : type == "plane"                  ? "point"
                           : type == "cylinder"               ? "top"
                           : type == "rectangle"              ? "edge_u"
                           : v.has("max")                     ? "max"
                                                              : "size";
    r.fail(v.has("transform") ? "transform" : size_key, e);
  }
  c.scene->shapes.push_back(sh);
}

// A black, emitting material for an area light: the default kind, black, emitting.
uint32_t emissive_material(Scene& s, const std::string& name, Color radiance, bool two_sided) {
  std::unique_ptr<Material> m = make_material(toml::table{{"name", name}});
  m->base_color = Texture::constant({0, 0, 0});
  m->emission = Texture::constant(radiance);
  m->double_sided = two_sided;
  s.materials.push_back(std::move(m));
  return uint32_t(s.materials.size() - 1);
}

// Area lights are real emissive geometry: the camera and reflections see them, and the light
// sampler finds them among the emissive triangles (quads) and spheres.
void add_area_light(const TableReader& r, const ParamValues& v, const std::string& name,
                    double strength, Scene& s) {
  if (v.string("type") == "quad") {
    const Vec3 corner = v.vec3("corner"), eu = v.vec3("edge_u"), ev = v.vec3("edge_v");
    if (!(length(cross(eu, ev)) > 0)) r.fail("edge_v", "edge_u and edge_v must span an area");
    const uint32_t mat =
        emissive_material(s, name, v.color("radiance") * strength, v.boolean("two_sided"));
    TriangleMesh m;
    m.name = name;
    for (const Vec3& p : {corner, corner + eu, corner + eu + ev, corner + ev})
      m.positions.push_back(Vec3f(p));
    // Counter-clockwise seen from the emitting side (edge_u x edge_v).
    m.indices = {0, 1, 2, 0, 2, 3};
    m.material = mat;
    Bounds3 box;
    for (const Vec3f& p : m.positions) box.extend(Vec3(p));
    if (const std::string e = placement_error(Transform(), box); !e.empty()) r.fail("edge_u", e);
    Prototype pr;
    pr.name = name;
    pr.meshes.push_back(std::move(m));
    s.prototypes.push_back(std::move(pr));
    s.instances.push_back(Instance{uint32_t(s.prototypes.size() - 1), Transform(), name, {}});
    return;
  }
  AnalyticShape sh;
  sh.kind = AnalyticShape::Kind::Sphere;
  sh.name = name;
  sh.radius = v.number("radius");
  sh.world_from_object = Transform::translate(v.vec3("center"));
  if (const std::string e = placement_error(sh.world_from_object, shape_object_bounds(sh));
      !e.empty())
    r.fail("radius", e);
  sh.material = emissive_material(s, name, v.color("radiance") * strength, true);
  s.shapes.push_back(sh);
}

void read_light(const TableReader& r, Scene& s, int index) {
  const ParamValues v = r.params(light_schema());
  const std::string type = v.string("type");
  const std::string name = v.has("name") ? v.string("name") : fmt::format("{}{}", type, index);
  const double strength = v.number("strength");
  if (type == "quad" || type == "sphere") {
    add_area_light(r, v, name, strength, s);
    return;
  }
  Light l;
  l.name = name;
  const auto direction = [&] {
    const Vec3 d = v.has("look_at") ? v.vec3("look_at") - l.position : v.vec3("direction");
    if (!(length(d) > 0)) r.fail("direction", "must not be zero");
    return normalize(d);
  };
  if (type == "directional") {
    l.kind = Light::Kind::Directional;
    l.direction = direction();
    l.intensity = v.color("irradiance") * strength;
  } else {
    l.kind = type == "point" ? Light::Kind::Point : Light::Kind::Spot;
    l.position = v.vec3("position");
    l.intensity = v.color("intensity") * strength;
    if (l.kind == Light::Kind::Spot) {
      l.direction = direction();
      l.cone_angle = v.number("cone_angle");
      l.cone_falloff = v.number("cone_falloff");
    }
  }
  s.lights.push_back(l);
}

void read_environment(const TableReader& r, Scene& s, bool check_only) {
  const ParamValues v = r.params({environment_schema().common});
  Environment& e = s.environment;
  e.color = v.color("color");
  e.strength = v.number("strength");
  e.rotation = v.number("rotation");
  if (v.has("file") && !check_only) {
    const ReadRole role("the environment map");
    try {
      e.image = std::make_shared<Image>(read_image(v.string("file"), true));
    } catch (const std::exception& ex) {
      r.fail_at(*r.node("file"), "file", ex.what());
    }
  }
}

template <class F>
void for_each_table(const TableReader& root, std::string_view key, F&& f) {
  const toml::node* n = root.node(key);
  if (!n) return;
  const toml::array* a = n->as_array();
  if (!a || !a->is_array_of_tables())
    root.fail(key, fmt::format("expected an array of tables ([[{}]] entries)", key));
  int i = 0;
  for (const auto& e : *a) {
    const TableReader r(*e.as_table(), fmt::format("{}[{}]", key, i));
    f(r, i);
    ++i;
  }
}

// A sub-table of the top level (an error when it is not a table), or null.
const toml::table* sub_table(const TableReader& top, std::string_view key) {
  const toml::node* n = top.node(key);
  if (n && !n->is_table()) top.fail(key, "expected a table");
  return n ? n->as_table() : nullptr;
}

// The scene text at a (fractional) frame: animation evaluated, then the overrides.
toml::table at_frame(const toml::table& original, const std::vector<std::string>& overrides,
                     double frame) {
  toml::table root = original;
  const std::vector<AnimatedKey> animation = take_animation(root);
  for (const AnimatedKey& a : animation)
    set_path(root, a.key, *value_node(a, frame).get("v"), a.loc);
  for (const auto& o : overrides) apply_override(root, o);
  return root;
}

// The [[object]] tables `overrides` place ("object.N.transform=..." or a key under it).
std::set<int> placed_tables(const std::vector<std::string>& overrides) {
  std::set<int> tables;
  for (const std::string& o : overrides) {
    if (o.rfind("object.", 0) != 0) continue;
    const size_t dot = o.find('.', 7), end = dot + 10;
    if (dot != std::string::npos && o.compare(dot, 10, ".transform") == 0 && end < o.size() &&
        (o[end] == '=' || o[end] == '.'))
      tables.insert(std::atoi(o.c_str() + 7));
  }
  return tables;
}

// A view's mesh objects with their transforms, read again when `overrides` place objects (the
// geometry stays the loaded scene's, moved by place_objects); the others are not read.
void read_object_transforms(const TableReader& top, const std::vector<std::string>& overrides,
                            Scene& s) {
  const std::set<int> placed = placed_tables(overrides);
  if (placed.empty()) return;
  for_each_table(top, "object", [&](const TableReader& r, int i) {
    const ParamValues v = r.params(object_schema());
    if (v.string("type") != "mesh") {
      if (placed.count(i))
        r.fail("transform", "only a mesh object moves without a load: load the scene with it");
      return;
    }
    PlacedObject p;
    p.table = i;
    p.transform = transform_or_identity(v, "transform");
    s.placed_objects.push_back(std::move(p));
  });
}

// Materials, objects, lights and the environment of a scene.
void read_world(Context& c, const TableReader& top) {
  Scene& s = *c.scene;
  // Material 0 is the default for objects without one: a [[material]] with only its name.
  s.materials.push_back(make_material(toml::table{{"name", "default"}}));
  for_each_table(top, "material", [&](const TableReader& r, int) {
    std::unique_ptr<Material> m = read_material(r, c.check_only);
    if (c.material_ids.count(m->name))
      r.fail("name", fmt::format("material \"{}\" is defined twice", m->name));
    c.material_ids[m->name] = uint32_t(s.materials.size());
    const toml::node* at = r.node("name");
    c.material_sites[m->name] = {at ? loc_of(*at) : loc_of(r.table()), r.full_key("name")};
    s.materials.push_back(std::move(m));
  });
  for_each_table(top, "object", [&](const TableReader& r, int i) { read_object(c, r, i); });
  for_each_table(top, "light", [&](const TableReader& r, int i) { read_light(r, s, i); });
  if (const toml::table* t = sub_table(top, "environment"))
    read_environment(TableReader(*t, "environment"), s, c.check_only);
}

template <class E>
E choice(const ParamValues& v, std::string_view key, std::span<const std::string_view> names) {
  return E(std::find(names.begin(), names.end(), v.string(key)) - names.begin());
}

// [render]: the declared keys, and the defaults that depend on other keys.
void read_render(const TableReader& r, RenderSettings& rs) {
  const ParamValues v = r.params({render_schema().common});
  select_integrator(rs, v.string("integrator"));  // (a declared choice: checked by params())
  rs.spp = int(v.integer("spp"));
  rs.sampler = choice<SamplerKind>(v, "sampler", sampler_names());
  rs.max_depth = int(v.integer("max_depth"));
  rs.bailout = v.number("bailout");
  rs.seed = uint64_t(v.integer("seed"));
  rs.filter = choice<PixelFilter>(v, "filter", filter_names());
  rs.filter_radius = v.number("filter_radius");
  rs.tile_size = int(v.integer("tile_size"));
  // Whitted antialiases adaptively unless the file asks for a fixed sampler or scheme.
  const bool whitted = rs.deterministic();
  const std::string aa = v.has("antialias")                              ? v.string("antialias")
                         : whitted && !r.has("sampler") && !r.has("spp") ? "adaptive"
                                                                         : "uniform";
  rs.antialias = aa == "uniform"                                    ? Antialias::Uniform
                 : aa == "lattice" || (aa == "adaptive" && whitted) ? Antialias::Lattice
                                                                    : Antialias::Pixel;
  // The lattice compares single samples: path tracing's noise would split every square.
  if (rs.antialias == Antialias::Lattice && rs.view == View::Beauty && !rs.deterministic())
    r.fail("antialias", fmt::format("\"lattice\" compares single samples, and the noise of "
                                    "`{}` would split every square: use \"pixel\" (or "
                                    "\"adaptive\") with it",
                                    rs.integrator));
  rs.aa_threshold = v.number("aa_threshold");
  rs.aa_depth = int(v.integer("aa_depth"));
  rs.aa_distortion = v.boolean("aa_distortion");
  // Whitted's samples differ only where the pixel holds detail: two find most of it.
  rs.min_spp = v.has("min_spp") ? int(v.integer("min_spp")) : whitted ? 2 : 8;
  rs.max_spp = v.has("max_spp") ? int(v.integer("max_spp")) : r.has("spp") ? rs.spp : 1024;
  if (v.has("max_spp") && rs.max_spp < rs.min_spp)
    r.fail_at(*r.node("max_spp"), "max_spp", range_error(rs.max_spp, rs.min_spp, kInf));
  rs.noise_threshold = v.number("noise_threshold");
  rs.time_limit = v.number("time_limit");
}

// What build_scene reads: everything (load_scene); only image, render and camera (load_view);
// every key without reading models and images (check_scene_frame). The last two take the model
// cameras of `loaded`, a scene loaded from the same file.
enum class Build { Full, View, Check };

// Whether the scene keeps its text (effective_toml, camera_toml): not for the solver's cameras,
// built many times from one parsed text (ViewTemplate), whose texts nobody reads.
enum class Texts { Keep, Skip };

// The frame's keys applied to `root` (animated values, then the command line's overrides), and
// what the scene records of them.
void apply_frame_keys(toml::table& root, const std::vector<AnimatedKey>& animation,
                      const std::vector<std::string>& overrides, double frame, Scene& s,
                      Texts texts) {
  for (const AnimatedKey& a : animation)
    set_path(root, a.key, *value_node(a, frame).get("v"), a.loc);
  for (const auto& o : overrides) apply_override(root, o);
  s.frame = frame;
  if (texts == Texts::Keep) s.effective_toml = to_toml_text(root);
  for (const AnimatedKey& a : animation) {
    s.first_key = s.animated.empty() ? a.frames.front() : std::min(s.first_key, a.frames.front());
    s.last_key = s.animated.empty() ? a.frames.back() : std::max(s.last_key, a.frames.back());
    s.animated.push_back(a.key);
  }
}

// [animation], [image] and [render], after checking the top level's keys (`include` was merged
// already; the tables are read by their own readers).
void read_settings(const TableReader& top, Scene& s) {
  static constexpr std::string_view kTables[] = {"image",       "render",  "camera",
                                                 "material",    "object",  "light",
                                                 "environment", "animate", "animation"};
  top.params({top_level_params()}, kTables);
  if (const toml::table* t = sub_table(top, "animation")) {
    const ParamValues v = TableReader(*t, "animation").params({animation_schema().common});
    s.fps = v.number("fps");
    s.motion_steps = int(v.integer("motion_steps"));
  }
  if (const toml::table* t = sub_table(top, "image")) {
    const ParamValues v = TableReader(*t, "image").params({image_schema().common});
    s.render.width = int(v.integer("width"));
    s.render.height = int(v.integer("height"));
  }
  if (const toml::table* t = sub_table(top, "render"))
    read_render(TableReader(*t, "render"), s.render);
}

// The model cameras (glTF) at rest, and the rigs that move them over the animation.
struct ModelCameraRigs {
  std::vector<ModelCamera> rest;
  const std::vector<SceneRig>* rigs;
  double fps;
  std::vector<ModelCamera> at(double frame) const {
    std::vector<ModelCamera> cams = rest;
    pose_model_cameras(*rigs, fps, frame, cams);
    return cams;
  }
};

// The world (objects, materials, lights, environment) unless `from` (a scene loaded from the
// same file) lends it, and the model cameras posed at the frame.
ModelCameraRigs read_world_and_model_cameras(Context& c, const TableReader& top,
                                             const Scene* from) {
  Scene& s = *c.scene;
  const std::vector<SceneRig>* rigs = &s.rigs;
  if (from) {
    // (The world was read, and validated, when `from` was loaded; nothing in it is animated
    // by [[animate]] keys.)
    s.model_cameras = from->model_cameras;
    rigs = &from->rigs;
  }
  if (!from || c.check_only) read_world(c, top);
  ModelCameraRigs m{s.model_cameras, rigs, s.fps};
  s.model_cameras = m.at(s.frame);
  return m;
}

// [camera]; with a shutter, the camera at shutter open and its rig at close (from the animation).
CameraSpec read_scene_camera(const TableReader& top, const toml::table& original,
                             const std::vector<std::string>& overrides, const ModelCameraRigs& rigs,
                             Scene& s, Texts texts) {
  const toml::table empty;
  const auto camera_table = [&](const toml::table& root) -> const toml::table& {
    const toml::node* n = root.get("camera");
    return n && n->is_table() ? *n->as_table() : empty;
  };
  const bool preset_overridden =
      std::any_of(overrides.begin(), overrides.end(),
                  [](const std::string& o) { return o.rfind("camera.preset=", 0) == 0; });
  const ImageInfo size{s.render.width, s.render.height};
  const toml::table* cn = sub_table(top, "camera");
  const toml::table& ct = cn ? *cn : empty;
  CameraSpec cam =
      read_camera(TableReader(ct, "camera"), size, s.model_cameras, preset_overridden, &s.warnings);
  if (texts == Texts::Keep) s.camera_toml = to_toml_text(ct);
  if (cam.shutter_close <= cam.shutter_open && cam.shutter_open == 0) return cam;
  const auto camera_at = [&](double t) {
    const toml::table r2 = at_frame(original, overrides, s.frame + t);
    return read_camera(TableReader(camera_table(r2), "camera"), size, rigs.at(s.frame + t),
                       preset_overridden, nullptr);
  };
  const Shutter shutter = cam.parts.shutter;
  if (cam.shutter_open != 0) {
    CameraSpec open = camera_at(cam.shutter_open);
    cam.parts = std::move(open.parts);
    cam.dof = open.dof;
    cam.parts.shutter = shutter;
  }
  cam.parts.world_from_camera_close = camera_at(cam.shutter_close).parts.world_from_camera;
  return cam;
}

// The scene at `frame` from `root` (its [[animate]] entries taken out into `animation`;
// `original` is root as it was, for the shutter's extra camera builds).
Scene build_frame(toml::table& root, const toml::table& original,
                  const std::vector<AnimatedKey>& animation, const fs::path& file,
                  const std::vector<std::string>& overrides, double frame, Build build,
                  const Scene* loaded, Texts texts) {
  const Scene* view_from = build == Build::View ? loaded : nullptr;
  Scene s;
  apply_frame_keys(root, animation, overrides, frame, s, texts);
  s.path = file.string();
  Context c;
  c.dir = file.parent_path();
  c.scene = &s;
  c.check_only = build == Build::Check;
  const TableReader top(root, "");
  read_settings(top, s);
  const Scene* lender = view_from ? view_from : c.check_only ? loaded : nullptr;
  const ModelCameraRigs rigs = read_world_and_model_cameras(c, top, lender);
  if (view_from) read_object_transforms(top, overrides, s);
  if (is_gltf_scene_file(file)) {
    complete_gltf_view(root, lender ? *lender : s, s.model_cameras, s.render);
    s.effective_toml = to_toml_text(root);
  }
  CameraSpec cam = read_scene_camera(top, original, overrides, rigs, s, texts);
  s.shutter_open = cam.shutter_open;
  s.shutter_close = cam.shutter_close;
  if (build == Build::Full) pose_scene(s, frame);
  s.camera = std::make_unique<VirtualCamera>(std::move(cam.parts), cam.dof);
  for (const std::string& w : s.camera->coin_warnings()) s.warnings.push_back("camera." + w);
  warn_if_no_rays(*s.camera, &s.warnings);
  return s;
}

Scene build_scene(toml::table root, const fs::path& file, const std::vector<std::string>& overrides,
                  double frame, Build build = Build::Full, const Scene* loaded = nullptr,
                  Texts texts = Texts::Keep) {
  // Copies lose their source positions, so the main build works on `root` itself, whose errors
  // point into the files.
  const toml::table original = root;
  const std::vector<AnimatedKey> animation = take_animation(root);
  try {
    return build_frame(root, original, animation, file, overrides, frame, build, loaded, texts);
  } catch (const SceneError& e) {
    throw at_animate_entry(e, animation, overrides, frame);
  }
}

// The scene's own file name (from the command line, Python or the editor): a NUL would cut it
// short.
void check_scene_path(const fs::path& file) {
  if (has_nul(file.native()))
    throw SceneError({file.native()}, "", nul_in_path_message(file.native(), false));
}

}  // namespace

namespace {

// `load` with every file it reads recorded in the scene's `inputs`.
template <class Load>
Scene recording_reads(Load&& load) {
  ReadLog log;
  Scene s;
  {
    const ReadLogScope scope(&log);
    s = load();
  }
  s.inputs = log.files();
  return s;
}

}  // namespace

Scene load_scene(const fs::path& file, const std::vector<std::string>& overrides, double frame) {
  check_scene_path(file);
  if (!fs::exists(file)) throw SceneError({file.string()}, "", "scene file not found");
  return recording_reads(
      [&] { return build_scene(load_with_includes(file), file, overrides, frame); });
}

namespace {

bool keys_animate_view_only(const Scene& s) {
  return std::all_of(s.animated.begin(), s.animated.end(), [](const std::string& k) {
    return k.rfind("camera.", 0) == 0 || k.rfind("image.", 0) == 0 || k.rfind("render.", 0) == 0;
  });
}

}  // namespace

bool animates_view_only(const Scene& s) {
  return !gltf_moves_world(s) && keys_animate_view_only(s);
}

bool animates_view_and_pose(const Scene& s) {
  return gltf_moves_world(s) && keys_animate_view_only(s);
}

Scene load_view(const fs::path& file, const std::vector<std::string>& overrides, double frame,
                const Scene& loaded) {
  check_scene_path(file);
  if (!fs::exists(file)) throw SceneError({file.string()}, "", "scene file not found");
  return recording_reads([&] {
    return build_scene(load_with_includes(file), file, overrides, frame, Build::View, &loaded);
  });
}

void check_scene_frame(const fs::path& file, const std::vector<std::string>& overrides,
                       double frame, const Scene& loaded) {
  check_scene_path(file);
  if (!fs::exists(file)) throw SceneError({file.string()}, "", "scene file not found");
  build_scene(load_with_includes(file), file, overrides, frame,
              animates_view_only(loaded) ? Build::View : Build::Check, &loaded);
}

namespace {

toml::table parse_scene_text(const std::string& text, const fs::path& name) {
  toml::table t;
  try {
    t = parse_toml(text, name.string());
  } catch (const toml::parse_error& e) {
    SourceLoc l{name.string(), int(e.source().begin.line), int(e.source().begin.column)};
    throw SceneError(l, "", fmt::format("TOML syntax error: {}", e.description()));
  }
  int files_read = 1;
  return merge_includes(std::move(t), name, 0, &files_read);
}

}  // namespace

Scene load_scene_from_string(const std::string& text, const fs::path& name,
                             const std::vector<std::string>& overrides, double frame) {
  return recording_reads([&] {
    {
      const ReadRole role("the scene file");  // (its text comes from the caller)
      note_read(name);
    }
    return build_scene(parse_scene_text(text, name), name, overrides, frame);
  });
}

Scene load_view_from_string(const std::string& text, const fs::path& name,
                            const std::vector<std::string>& overrides, double frame,
                            const Scene& loaded) {
  return recording_reads([&] {
    {
      const ReadRole role("the scene file");
      note_read(name);
    }
    return build_scene(parse_scene_text(text, name), name, overrides, frame, Build::View, &loaded);
  });
}

struct ViewTemplate::Parsed {
  toml::table root;
  std::vector<std::string> without;
};

namespace {

// Whether the dotted `key` ("camera.constraint.0.uv") lies in one of the tables `without`.
bool under_any(const std::string& key, const std::vector<std::string>& without) {
  return std::any_of(without.begin(), without.end(), [&](const std::string& w) {
    return key == w || key.starts_with(w + ".") || key.starts_with(w + "[");
  });
}

}  // namespace

ViewTemplate::ViewTemplate(const std::string& text, const fs::path& name,
                           const std::vector<std::string>& without)
    : parsed_(std::make_unique<Parsed>()), name_(name) {
  parsed_->root = parse_scene_text(text, name);
  parsed_->without = without;
  std::vector<std::string> other;
  for (const auto& [key, node] : parsed_->root)
    if (key != "image" && key != "render" && key != "camera" && key != "animate" &&
        key != "animation")
      other.emplace_back(key.str());
  for (const std::string& k : other) parsed_->root.erase(k);
  for (const std::string& k : without) remove_path(parsed_->root, k);
  // [[animate]] entries of the tables taken out go with them.
  toml::array* animate = parsed_->root.get_as<toml::array>("animate");
  if (!animate || without.empty()) return;
  const auto under_removed = [&](const toml::node& e) {
    const toml::table* t = e.as_table();
    const toml::value<std::string>* k = t ? t->get_as<std::string>("key") : nullptr;
    return k && under_any(k->get(), without);
  };
  for (size_t i = animate->size(); i-- > 0;)
    if (under_removed(*animate->get(i))) animate->erase(animate->begin() + std::ptrdiff_t(i));
  if (animate->empty()) parsed_->root.erase("animate");
}

ViewTemplate::~ViewTemplate() = default;

Scene ViewTemplate::build(const std::vector<std::string>& overrides, double frame,
                          const Scene& loaded) const {
  // (Overrides of the tables taken out go with them.)
  std::vector<std::string> kept;
  for (const std::string& o : overrides)
    if (!under_any(o.substr(0, o.find('=')), parsed_->without)) kept.push_back(o);
  return build_scene(parsed_->root, name_, kept, frame, Build::View, &loaded, Texts::Skip);
}

}  // namespace anamorph
