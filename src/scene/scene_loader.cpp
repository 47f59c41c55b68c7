#include "scene/scene_loader.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "io/image_io.h"
#include "math/frame.h"
#include "scene/animation.h"
#include "scene/camera_reader.h"
#include "scene/load_common.h"
#include "scene/loaders.h"
#include "scene/toml_reader.h"

namespace anamorph {

namespace fs = std::filesystem;

namespace {

const std::string_view kIntegrators[] = {"whitted", "path",     "albedo", "normal",
                                         "depth",   "position", "id",     "uv"};
const std::string_view kSamplers[] = {"center", "stratified", "random"};
const std::string_view kFilters[] = {"box", "gaussian"};
const std::string_view kAntialias[] = {"uniform", "adaptive", "lattice", "pixel"};
const std::string_view kObjectTypes[] = {"mesh", "sphere", "plane", "box", "cylinder", "disk"};
const std::string_view kLightTypes[] = {"point", "spot", "directional", "quad", "sphere"};
const std::string_view kMaterialTypes[] = {"whitted", "metallic_roughness"};
const std::string_view kTextureTypes[] = {"checker", "grid", "image"};
const std::string_view kSpaces[] = {"uv", "object", "world"};
const std::string_view kWraps[] = {"repeat", "clamp", "mirror"};

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
      "never finite, or vanish); the image will be transparent",
      n * n));
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
    return toml::parse(text, file.string());
  } catch (const toml::parse_error& e) {
    SourceLoc l;
    l.file = file.string();
    l.line = int(e.source().begin.line);
    l.column = int(e.source().begin.column);
    throw SceneError(l, "", fmt::format("TOML syntax error: {}", e.description()));
  }
}

// Tables merge key by key, arrays of tables concatenate (base first), other values: `over` wins.
void merge_into(toml::table& base, const toml::table& over) {
  for (const auto& [k, v] : over) {
    toml::node* b = base.get(k.str());
    if (b && b->is_table() && v.is_table()) {
      merge_into(*b->as_table(), *v.as_table());
    } else if (b && b->is_array_of_tables() && v.is_array_of_tables()) {
      for (const auto& e : *v.as_array()) b->as_array()->push_back(e);
    } else {
      base.insert_or_assign(k, v);
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

toml::table load_with_includes(const fs::path& file, int depth, int* files_read) {
  if (depth > kMaxIncludeDepth)
    throw SceneError({file.string()}, "include", "includes nested too deeply (a cycle?)");
  if (++*files_read > kMaxIncludedFiles)
    throw SceneError({file.string()}, "include",
                     fmt::format("more than {} files included in all (a cycle, or includes that "
                                 "fan out level after level?)",
                                 kMaxIncludedFiles));
  toml::table t = parse_toml_file(file);
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
    const fs::path p = file.parent_path() / f;
    if (!fs::exists(p)) r.fail("include", fmt::format("included file not found: {}", p.string()));
    toml::table inc_table = load_with_includes(p, depth + 1, files_read);
    anchor_paths(inc_table, p.parent_path());
    merge_into(merged, inc_table);
  }
  t.erase("include");
  merge_into(merged, t);
  return merged;
}

toml::table load_with_includes(const fs::path& file) {
  int files_read = 0;
  return load_with_includes(file, 0, &files_read);
}

toml::table parse_value_text(const std::string& text) {
  try {
    return toml::parse("v = " + text);
  } catch (const toml::parse_error&) {
    toml::table t;
    t.insert("v", text);  // a bare word: a string
    return t;
  }
}

// Sets the value at a dotted path; numeric parts index arrays (arrays of tables and plain
// arrays alike, e.g. camera.coin.0.strength or camera.org.points.1.2).
void set_path(toml::table& root, const std::string& key, const toml::node& value,
              const SourceLoc& where) {
  std::vector<std::string> parts;
  for (size_t s = 0, e; s <= key.size(); s = e + 1) {
    e = key.find('.', s);
    if (e == std::string::npos) e = key.size();
    parts.push_back(key.substr(s, e - s));
  }
  auto index = [&](const toml::array& a, const std::string& p) {
    char* end = nullptr;
    const long idx = std::strtol(p.c_str(), &end, 10);
    if (p.empty() || *end || idx < 0 || size_t(idx) >= a.size())
      throw SceneError(
          where, key,
          fmt::format("'{}' is not a valid index (the array has {} entries)", p, a.size()));
    return size_t(idx);
  };
  toml::node* cur = &root;
  for (size_t i = 0; i + 1 < parts.size(); ++i) {
    const std::string& p = parts[i];
    if (toml::array* a = cur->as_array()) {
      cur = a->get(index(*a, p));
    } else if (toml::table* t = cur->as_table()) {
      if (!t->contains(p)) t->insert(p, toml::table{});
      cur = t->get(p);
    } else {
      throw SceneError(where, key, fmt::format("'{}' is not a table or an array", p));
    }
  }
  if (toml::array* a = cur->as_array()) {
    const size_t i = index(*a, parts.back());
    a->replace(a->cbegin() + long(i), value);
  } else if (toml::table* t = cur->as_table()) {
    t->insert_or_assign(parts.back(), value);
  } else {
    throw SceneError(where, key, "can only set keys of tables or entries of arrays");
  }
}

void apply_override(toml::table& root, const std::string& kv) {
  const size_t eq = kv.find('=');
  if (eq == std::string::npos || eq == 0)
    throw SceneError({}, kv, "expected --set KEY=VALUE (e.g. --set camera.fov=90)");
  const toml::table value = parse_value_text(kv.substr(eq + 1));
  set_path(root, kv.substr(0, eq), *value.get("v"), {});
}

// ---- materials and textures -------------------------------------------------------------------

struct Context {
  fs::path dir;  // relative paths resolve against the scene file's directory
  Scene* scene;
  std::map<std::string, uint32_t> material_ids;
};

fs::path resolve(const Context& c, TableReader& r, std::string_view key) {
  const std::string f = r.string(key, "");
  if (f.empty()) r.fail(key, "is required (a file path, relative to the scene file)");
  fs::path p = f;
  if (p.is_relative()) {
    // The key's own file: an included file's paths are relative to that file.
    const toml::node* n = r.table().get(key);
    const SourceLoc l = loc_of(*n);
    p = (l.file.empty() ? c.dir : fs::path(l.file).parent_path()) / p;
  }
  if (!fs::exists(p)) r.fail(key, fmt::format("file not found: {}", p.string()));
  return p;
}

Texture read_texture(Context& c, TableReader& r, std::string_view key, Color def, bool srgb) {
  const toml::node* n = r.table().get(key);
  if (!n || !n->is_table()) return Texture::constant(r.color(key, def));
  r.allow(key);
  TableReader t(*n->as_table(), r.full_key(key));
  const std::string type = t.string("type", "", kTextureTypes);
  if (type.empty()) t.fail("type", "is required (checker, grid or image)");
  Texture tex;
  if (type == "image") {
    tex.kind = Texture::Kind::Image;
    const fs::path p = resolve(c, t, "file");
    try {
      tex.image = std::make_shared<MipMap>(read_image(p, srgb));
    } catch (const std::exception& e) {
      t.fail("file", e.what());
    }
    tex.value = t.color("scale_color", {1, 1, 1});
    const std::string w = t.string("wrap", "repeat", kWraps);
    tex.wrap_s = tex.wrap_t =
        w == "clamp" ? Wrap::Clamp : (w == "mirror" ? Wrap::Mirror : Wrap::Repeat);
    tex.nearest = t.boolean("nearest", false);
    const Vec3 off = t.vec3("uv_offset", {0, 0, 0});
    const Vec3 sc = t.vec3("uv_scale", {1, 1, 1});
    tex.uv_transform = UvTransform::from_offset_rotation_scale(
        {off.x, off.y}, radians(t.number("uv_rotation", 0)), {sc.x, sc.y});
  } else {
    tex.kind = type == "checker" ? Texture::Kind::Checker : Texture::Kind::Grid;
    const std::string s = t.string("space", type == "checker" ? "world" : "uv", kSpaces);
    tex.space = s == "uv" ? Texture::Space::Uv
                          : (s == "object" ? Texture::Space::Object : Texture::Space::World);
    tex.color_a = t.color("color_a", {0.9, 0.9, 0.9});
    tex.color_b = t.color("color_b", {0.1, 0.1, 0.1});
    tex.scale = t.number("scale", 1.0, 1e-9, kInf);
    tex.line_width = t.number("line_width", 0.05, 0, 1);
    tex.pattern_from_space = t.transform("transform").inverse();
  }
  t.finish();
  return tex;
}

Material read_material(Context& c, TableReader& r) {
  Material m;
  m.name = r.string("name", "");
  if (m.name.empty()) r.fail("name", "is required (objects refer to materials by name)");
  const std::string type = r.string("type", "whitted", kMaterialTypes);
  m.model = type == "whitted" ? Material::Model::Whitted : Material::Model::MetallicRoughness;
  m.base_color = read_texture(c, r, "color", {0.8, 0.8, 0.8}, true);
  m.emission = read_texture(c, r, "emission", {0, 0, 0}, true);
  m.emission_strength = r.number("emission_strength", 1, 0);
  m.ior = r.number("ior", 1.5, 1.0, 10);
  if (m.model == Material::Model::Whitted) {
    m.diffuse = r.number("diffuse", 1, 0, 1);
    m.specular = r.color("specular", {0, 0, 0});
    m.exponent = r.number("exponent", 50, 0);
    m.reflectivity = r.number("reflectivity", 0, 0, 1);
    m.transmission = r.number("transmission", 0, 0, 1);
    if (m.reflectivity + m.transmission > 1)
      r.fail("transmission", "reflectivity + transmission must not exceed 1 (energy conservation)");
  } else {
    m.metallic = r.number("metallic", 0, 0, 1);
    m.roughness = r.number("roughness", 0.5, 0, 1);
    m.transmission = r.number("transmission", 0, 0, 1);
  }
  m.double_sided = r.boolean("double_sided", true);
  r.finish();
  return m;
}

uint32_t material_ref(Context& c, TableReader& r, std::string_view key) {
  const std::string name = r.string(key, "");
  if (name.empty()) return 0;  // the default material
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

void read_object(Context& c, TableReader& r, int index) {
  Scene& s = *c.scene;
  const std::string type = r.string("type", "", kObjectTypes);
  if (type.empty()) r.fail("type", "is required (mesh, sphere, plane, box, cylinder or disk)");
  const std::string name = r.string("name", fmt::format("{}{}", type, index));
  const Transform xf = r.transform("transform");
  if (type == "mesh") {
    const fs::path p = resolve(c, r, "file");
    LoadedModel m;
    try {
      m = load_model(p);
    } catch (const std::exception& e) {
      r.fail("file", e.what());
    }
    const bool override_mat = r.has("material");
    const uint32_t mat = material_ref(c, r, "material");
    const auto mat_base = uint32_t(s.materials.size());
    if (!override_mat)
      for (auto& mm : m.materials) s.materials.push_back(std::move(mm));
    const auto proto_base = uint32_t(s.prototypes.size());
    for (auto& pr : m.prototypes) {
      for (auto& mesh : pr.meshes) mesh.material = override_mat ? mat : mesh.material + mat_base;
      s.prototypes.push_back(std::move(pr));
    }
    for (auto& inst : m.instances) {
      inst.prototype += proto_base;
      inst.world_from_object = xf * inst.world_from_object;
      inst.name = name + (inst.name.empty() ? "" : "/" + inst.name);
      s.instances.push_back(std::move(inst));
    }
    for (auto& cam : m.cameras) {
      cam.world_from_camera = xf * cam.world_from_camera;
      c.scene->model_cameras.push_back(cam);
    }
    for (auto& w : m.warnings) s.warnings.push_back(w);
    r.finish();
    return;
  }
  AnalyticShape sh;
  sh.name = name;
  sh.material = material_ref(c, r, "material");
  if (type == "sphere") {
    sh.kind = AnalyticShape::Kind::Sphere;
    sh.radius = r.number("radius", 1, 0, kInf);
    if (sh.radius <= 0) r.fail("radius", "must be > 0");
    sh.world_from_object = xf * Transform::translate(r.vec3("center", {0, 0, 0}));
  } else if (type == "plane") {
    sh.kind = AnalyticShape::Kind::Plane;
    const Vec3 n = r.vec3("normal", {0, 1, 0});
    if (!(length(n) > 0)) r.fail("normal", "must not be zero");
    sh.world_from_object = xf * Transform::translate(r.vec3("point", {0, 0, 0})) * y_to(n);
  } else if (type == "box") {
    sh.kind = AnalyticShape::Kind::Box;
    Vec3 center{0, 0, 0}, size{1, 1, 1};
    if (r.has("min") || r.has("max")) {
      const Vec3 lo = r.vec3("min", {-0.5, -0.5, -0.5}), hi = r.vec3("max", {0.5, 0.5, 0.5});
      center = (lo + hi) * 0.5;
      size = hi - lo;
      if (min_component(size) <= 0)
        r.fail("max", "max must be greater than min in every component");
    } else {
      center = r.vec3("center", center);
      size = r.vec3("size", size);
      if (min_component(size) <= 0) r.fail("size", "every component must be > 0");
    }
    sh.size = size;
    sh.world_from_object = xf * Transform::translate(center);
  } else if (type == "cylinder") {
    sh.kind = AnalyticShape::Kind::Cylinder;
    const Vec3 base = r.vec3("base", {0, 0, 0}), top = r.vec3("top", {0, 1, 0});
    sh.height = length(top - base);
    if (!(sh.height > 0)) r.fail("top", "top must differ from base");
    sh.radius = r.number("radius", 0.5, 0, kInf);
    if (sh.radius <= 0) r.fail("radius", "must be > 0");
    sh.capped = r.boolean("capped", true);
    sh.world_from_object = xf * Transform::translate(base) * y_to(top - base);
  } else {  // disk
    sh.kind = AnalyticShape::Kind::Disk;
    const Vec3 n = r.vec3("normal", {0, 1, 0});
    if (!(length(n) > 0)) r.fail("normal", "must not be zero");
    sh.radius = r.number("radius", 1, 0, kInf);
    if (sh.radius <= 0) r.fail("radius", "must be > 0");
    sh.world_from_object = xf * Transform::translate(r.vec3("center", {0, 0, 0})) * y_to(n);
  }
  r.finish();
  s.shapes.push_back(sh);
}

// A black, emitting material for an area light.
uint32_t emissive_material(Scene& s, const std::string& name, Color radiance, bool two_sided) {
  Material m;
  m.name = name;
  m.base_color = Texture::constant({0, 0, 0});
  m.emission = Texture::constant(radiance);
  m.double_sided = two_sided;
  s.materials.push_back(m);
  return uint32_t(s.materials.size() - 1);
}

void read_light(TableReader& r, Scene& s, int index) {
  Light l;
  const std::string type = r.string("type", "", kLightTypes);
  if (type.empty()) r.fail("type", "is required (point, spot, directional, quad or sphere)");
  l.name = r.string("name", fmt::format("{}{}", type, index));
  const double strength = r.number("strength", 1, 0);
  if (type == "point" || type == "spot") {
    l.kind = type == "point" ? Light::Kind::Point : Light::Kind::Spot;
    l.position = r.vec3("position", {0, 0, 0});
    l.intensity = r.color("intensity", {1, 1, 1}) * strength;
    if (l.kind == Light::Kind::Spot) {
      if (r.has("look_at"))
        l.direction = r.vec3("look_at", {}) - l.position;
      else
        l.direction = r.vec3("direction", {0, -1, 0});
      if (!(length(l.direction) > 0)) r.fail("direction", "must not be zero");
      l.direction = normalize(l.direction);
      l.cone_angle = r.number("cone_angle", 30, 0, 180);
      l.cone_falloff = r.number("cone_falloff", 5, 0, 180);
    }
  } else if (type == "directional") {
    l.kind = Light::Kind::Directional;
    l.direction = r.vec3("direction", {0, -1, 0});
    if (!(length(l.direction) > 0)) r.fail("direction", "must not be zero");
    l.direction = normalize(l.direction);
    l.intensity = r.color("irradiance", {1, 1, 1}) * strength;
  } else if (type == "quad") {
    // Area lights are real emissive geometry: the camera and reflections see them, and the
    // light sampler finds them among the emissive triangles.
    const Vec3 corner = r.vec3("corner", {0, 0, 0});
    const Vec3 eu = r.vec3("edge_u", {1, 0, 0}), ev = r.vec3("edge_v", {0, 0, 1});
    if (!(length(cross(eu, ev)) > 0)) r.fail("edge_v", "edge_u and edge_v must span an area");
    const uint32_t mat = emissive_material(s, l.name, r.color("radiance", {1, 1, 1}) * strength,
                                           r.boolean("two_sided", false));
    TriangleMesh m;
    m.name = l.name;
    for (const Vec3& p : {corner, corner + eu, corner + eu + ev, corner + ev})
      m.positions.push_back(Vec3f(p));
    // Counter-clockwise seen from the emitting side (edge_u x edge_v).
    m.indices = {0, 1, 2, 0, 2, 3};
    m.material = mat;
    Prototype pr;
    pr.name = l.name;
    pr.meshes.push_back(std::move(m));
    s.prototypes.push_back(std::move(pr));
    s.instances.push_back(Instance{uint32_t(s.prototypes.size() - 1), Transform(), l.name});
    r.finish();
    return;
  } else {
    AnalyticShape sh;
    sh.kind = AnalyticShape::Kind::Sphere;
    sh.name = l.name;
    sh.radius = r.number("radius", 0.5, 0);
    if (sh.radius <= 0) r.fail("radius", "must be > 0");
    sh.world_from_object = Transform::translate(r.vec3("center", {0, 0, 0}));
    sh.material = emissive_material(s, l.name, r.color("radiance", {1, 1, 1}) * strength, true);
    s.shapes.push_back(sh);
    r.finish();
    return;
  }
  r.finish();
  s.lights.push_back(l);
}

void read_environment(Context& c, TableReader& r, Scene& s) {
  Environment& e = s.environment;
  e.color = r.color("color", {0, 0, 0});
  e.strength = r.number("strength", 1, 0);
  e.rotation = r.number("rotation", 0);
  if (r.has("file")) {
    const fs::path p = resolve(c, r, "file");
    try {
      e.image = std::make_shared<Image>(read_image(p, true));
    } catch (const std::exception& ex) {
      r.fail("file", ex.what());
    }
  }
  r.finish();
}

template <class F>
void for_each_table(TableReader& root, std::string_view key, F&& f) {
  const toml::node* n = root.node(key);
  if (!n) return;
  const toml::array* a = n->as_array();
  if (!a || !a->is_array_of_tables())
    root.fail(key, fmt::format("expected an array of tables ([[{}]] entries)", key));
  int i = 0;
  for (const auto& e : *a) {
    TableReader r(*e.as_table(), fmt::format("{}[{}]", key, i));
    f(r, i);
    ++i;
  }
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

// Materials, objects, lights and the environment of a scene.
void read_world(Context& c, TableReader& top) {
  Scene& s = *c.scene;
  // Material 0 is the default for objects without one.
  Material def;
  def.name = "default";
  s.materials.push_back(def);
  for_each_table(top, "material", [&](TableReader& r, int) {
    Material m = read_material(c, r);
    if (c.material_ids.count(m.name))
      r.fail("name", fmt::format("material \"{}\" is defined twice", m.name));
    c.material_ids[m.name] = uint32_t(s.materials.size());
    s.materials.push_back(std::move(m));
  });
  for_each_table(top, "object", [&](TableReader& r, int i) { read_object(c, r, i); });
  for_each_table(top, "light", [&](TableReader& r, int i) { read_light(r, s, i); });
  if (const toml::node* n = top.node("environment")) {
    if (!n->is_table()) top.fail("environment", "expected a table");
    TableReader r(*n->as_table(), "environment");
    read_environment(c, r, s);
  }
}

// `view_from`: read only image, render and camera, with the model cameras of this scene
// (load_view).
Scene build_scene(toml::table root, const fs::path& file, const std::vector<std::string>& overrides,
                  double frame, const Scene* view_from = nullptr) {
  // Kept for the shutter's extra camera builds. Copies lose their source positions, so the main
  // build works on `root` itself, whose errors point into the files.
  const toml::table original = root;
  const std::vector<AnimatedKey> animation = take_animation(root);
  for (const AnimatedKey& a : animation)
    set_path(root, a.key, *value_node(a, frame).get("v"), a.loc);
  for (const auto& o : overrides) apply_override(root, o);
  Scene s;
  s.frame = frame;
  for (const AnimatedKey& a : animation) {
    s.first_key = s.animated.empty() ? a.frames.front() : std::min(s.first_key, a.frames.front());
    s.last_key = s.animated.empty() ? a.frames.back() : std::max(s.last_key, a.frames.back());
    s.animated.push_back(a.key);
  }
  s.path = file.string();
  Context c;
  c.dir = file.parent_path();
  c.scene = &s;
  TableReader top(root, "");

  if (const toml::node* n = top.node("image")) {
    if (!n->is_table()) top.fail("image", "expected a table");
    TableReader r(*n->as_table(), "image");
    s.render.width = int(r.integer("width", 640, 1, 65536));
    s.render.height = int(r.integer("height", 480, 1, 65536));
    r.finish();
  }
  if (const toml::node* n = top.node("render")) {
    if (!n->is_table()) top.fail("render", "expected a table");
    TableReader r(*n->as_table(), "render");
    RenderSettings& rs = s.render;
    rs.integrator = r.string("integrator", rs.integrator, kIntegrators);
    rs.spp = int(r.integer("spp", rs.spp, 1, 1 << 20));
    rs.sampler = r.string("sampler", rs.sampler, kSamplers);
    rs.max_depth = int(r.integer("max_depth", rs.max_depth, 0, 1000));
    rs.bailout = r.number("bailout", rs.bailout, 0, 1);
    rs.seed = uint64_t(r.integer("seed", 0, 0, std::numeric_limits<int64_t>::max()));
    rs.filter = r.string("filter", rs.filter, kFilters);
    rs.filter_radius = r.number("filter_radius", rs.filter_radius, 0.5, 8);
    rs.tile_size = int(r.integer("tile_size", rs.tile_size, 4, 1024));
    // Whitted antialiases adaptively unless the file asks for a fixed sampler or scheme.
    const bool whitted = rs.integrator == "whitted";
    rs.antialias = r.string("antialias",
                            whitted && !r.has("sampler") && !r.has("spp") ? "adaptive" : "uniform",
                            kAntialias);
    if (rs.antialias == "adaptive") rs.antialias = whitted ? "lattice" : "pixel";
    // The lattice compares single samples: path tracing's noise would split every square.
    if (rs.antialias == "lattice" && rs.integrator == "path")
      r.fail("antialias",
             "\"lattice\" compares single samples, and path tracing's noise would split every "
             "square: use \"pixel\" (or \"adaptive\") with path tracing");
    rs.aa_threshold = r.number("aa_threshold", rs.aa_threshold, 0, kInf);
    rs.aa_depth = int(r.integer("aa_depth", rs.aa_depth, 0, 6));
    rs.aa_distortion = r.boolean("aa_distortion", rs.aa_distortion);
    // Whitted's samples differ only where the pixel holds detail: two find most of it.
    rs.min_spp = int(r.integer("min_spp", whitted ? 2 : rs.min_spp, 1, 1 << 20));
    rs.max_spp = int(r.integer("max_spp", r.has("spp") ? rs.spp : rs.max_spp, rs.min_spp, 1 << 20));
    rs.noise_threshold = r.number("noise_threshold", rs.noise_threshold, 0, kInf);
    rs.time_limit = r.number("time_limit", rs.time_limit, 0, kInf);
    r.finish();
  }

  if (view_from) {
    // (Marked as read: they were validated when view_from was loaded, and nothing in them is
    // animated.)
    for (const char* key : {"material", "object", "light", "environment"}) top.node(key);
    s.model_cameras = view_from->model_cameras;
  } else {
    read_world(c, top);
  }

  const toml::node* cn = top.node("camera");
  if (cn && !cn->is_table()) top.fail("camera", "expected a table");
  const toml::table empty;
  const toml::table& ct = cn ? *cn->as_table() : empty;
  TableReader cr(ct, "camera");
  const bool preset_overridden =
      std::any_of(overrides.begin(), overrides.end(),
                  [](const std::string& o) { return o.rfind("camera.preset=", 0) == 0; });
  ShutterSpec shutter;
  s.camera = read_camera(cr, {s.render.width, s.render.height}, s.model_cameras, preset_overridden,
                         &s.warnings, &shutter);
  s.camera_toml = to_toml_text(ct);
  if (shutter.close > shutter.open || shutter.open != 0) {
    // Camera motion blur: the rig at shutter open and close, from the animation.
    auto camera_at = [&](double t) {
      const toml::table r2 = at_frame(original, overrides, frame + t);
      const toml::node* n2 = r2.get("camera");
      TableReader cr2(n2 && n2->is_table() ? *n2->as_table() : empty, "camera");
      ShutterSpec unused;
      return read_camera(cr2, {s.render.width, s.render.height}, s.model_cameras, preset_overridden,
                         nullptr, &unused);
    };
    if (shutter.open != 0) s.camera = camera_at(shutter.open);
    const auto close = camera_at(shutter.close);
    static_cast<VirtualCamera&>(*s.camera).set_motion(
        static_cast<const VirtualCamera&>(*close).rig(), shutter.shutter);
  } else if (shutter.shutter.rolling) {
    static_cast<VirtualCamera&>(*s.camera).set_motion(
        static_cast<const VirtualCamera&>(*s.camera).rig(), shutter.shutter);
  }
  warn_if_no_rays(*s.camera, &s.warnings);
  top.finish();
  return s;
}

}  // namespace

Scene load_scene(const fs::path& file, const std::vector<std::string>& overrides, double frame) {
  if (!fs::exists(file)) throw SceneError({file.string()}, "", "scene file not found");
  return build_scene(load_with_includes(file), file, overrides, frame);
}

bool animates_view_only(const Scene& s) {
  return std::all_of(s.animated.begin(), s.animated.end(), [](const std::string& k) {
    return k.rfind("camera.", 0) == 0 || k.rfind("image.", 0) == 0 || k.rfind("render.", 0) == 0;
  });
}

Scene load_view(const fs::path& file, const std::vector<std::string>& overrides, double frame,
                const Scene& loaded) {
  if (!fs::exists(file)) throw SceneError({file.string()}, "", "scene file not found");
  return build_scene(load_with_includes(file), file, overrides, frame, &loaded);
}

Scene load_scene_from_string(const std::string& text, const fs::path& name,
                             const std::vector<std::string>& overrides, double frame) {
  toml::table t;
  try {
    t = toml::parse(text, name.string());
  } catch (const toml::parse_error& e) {
    SourceLoc l{name.string(), int(e.source().begin.line), int(e.source().begin.column)};
    throw SceneError(l, "", fmt::format("TOML syntax error: {}", e.description()));
  }
  return build_scene(std::move(t), name, overrides, frame);
}

}  // namespace anamorph
