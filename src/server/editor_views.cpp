// What the editor shows about the camera on screen: the surface under an image position, the
// image positions of a point, the coins' sites, the magnification map and the rays' overview.
// Each waits until the document version it is asked about is the one the preview shows.
#include <cmath>

#include "accel/accel.h"
#include "render/renderer.h"
#include "scene/scene_loader.h"
#include "scene/toml_edit.h"
#include "scene/toml_reader.h"
#include "server/editor.h"

namespace anamorph::server {

namespace {
Bounds3 record_box(const Accel::Record& rec);
}  // namespace

std::optional<PickResult> Editor::pick(Vec2 uv, int64_t version) {
  PickResult r;
  const bool ok = preview_.with_state(version, 10, [&](const Scene& s, const Renderer& renderer) {
    CameraSample cs;
    cs.uv = uv;
    const std::optional<CameraRay> ray = s.camera->generate(cs);
    if (!ray) return;
    r.ray = true;
    Hit h;
    if (!renderer.accel().intersect(Ray{ray->org, ray->dir}, &h)) return;
    r.hit = true;
    r.position = h.p;
    r.normal = h.ns;
    r.distance = h.t;
    r.object = h.object_id;
    r.box = record_box(renderer.accel().record(h.object_id));
  });
  if (!ok) return std::nullopt;
  return r;
}

std::optional<std::vector<Vec2>> Editor::project(const Vec3& p, int64_t version) {
  std::vector<Vec2> uvs;
  const bool ok = preview_.with_state(
      version, 10, [&](const Scene& s, const Renderer&) { uvs = s.camera->project(p); });
  if (!ok) return std::nullopt;
  return uvs;
}

std::optional<std::vector<CoinSite>> Editor::coins(int64_t version) {
  std::vector<CoinSite> sites;
  const bool ok = preview_.with_state(version, 10, [&](const Scene& s, const Renderer&) {
    const auto all = coin_sites(*s.camera);
    sites.assign(all.begin(), all.end());
  });
  if (!ok) return std::nullopt;
  return sites;
}

namespace {

// The footprint of each ray's beam where it meets the scene, |dP/du x dP/dv| with
// P = org + t dir at the hit distance t (1 for a ray that meets nothing), at w x h pixel centers
// (NaN: no ray). A coin that pulls the origins toward its point magnifies there, not one unit
// away, so the distance matters.
std::vector<double> footprints(const Camera& cam, const Accel& accel, int w, int h) {
  std::vector<double> a(size_t(w) * h, std::nan(""));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      CameraSample cs;
      cs.uv = {(x + 0.5) / w, (y + 0.5) / h};
      const std::optional<CameraRay> r = cam.generate(cs);
      if (!r) continue;
      Hit hit;
      const double t = accel.intersect(Ray{r->org, r->dir}, &hit) ? hit.t : 1;
      a[size_t(y) * w + x] =
          length(cross(r->dorg_du + t * r->ddir_du, r->dorg_dv + t * r->ddir_dv));
    }
  return a;
}

}  // namespace

std::optional<std::vector<float>> Editor::magnification(int w, int h, int64_t version) {
  std::unique_ptr<Scene> plain;  // the camera without its coins
  {
    std::lock_guard lock(mu_);
    toml::table t = doc_.table();
    if (remove_path(t, "camera.coin") && models_) {
      // (and the keyframes of coin keys, which would name keys no longer there)
      if (toml::array* anim = t["animate"].as_array()) {
        for (size_t i = anim->size(); i-- > 0;) {
          const toml::table* e = (*anim)[i].as_table();
          const std::string key = e ? (*e)["key"].value_or(std::string()) : std::string();
          if (key == "camera.coin" || key.rfind("camera.coin.", 0) == 0)
            anim->erase(anim->cbegin() + long(i));
        }
        if (anim->empty()) t.erase("animate");
      }
      plain = std::make_unique<Scene>(
          load_view_from_string(to_toml_text(t), doc_.file(), {}, frame_, *models_));
    }
  }
  std::vector<double> a, ref;
  const bool ok = preview_.with_state(version, 10, [&](const Scene& s, const Renderer& r) {
    a = footprints(*s.camera, r.accel(), w, h);
    if (plain) ref = footprints(*plain->camera, r.accel(), w, h);
  });
  if (!ok) return std::nullopt;
  if (!plain) {
    double sum = 0;
    size_t n = 0;
    for (double x : a)
      if (std::isfinite(x) && x > 0) sum += x, ++n;
    ref.assign(a.size(), n ? sum / n : 1);
  }
  std::vector<float> m(a.size());
  for (size_t i = 0; i < a.size(); ++i)
    m[i] = std::isfinite(a[i]) && a[i] > 0 && std::isfinite(ref[i])
               ? float(std::sqrt(ref[i] / a[i]))
               : std::nanf("");
  return m;
}

namespace {

Bounds3 world_box(const Bounds3& object, const Transform& world_from_object) {
  Bounds3 b;
  for (int i = 0; i < 8; ++i)
    b.extend(world_from_object.point({i & 1 ? object.hi.x : object.lo.x,
                                      i & 2 ? object.hi.y : object.lo.y,
                                      i & 4 ? object.hi.z : object.lo.z}));
  return b;
}

// Object space bounds of an analytic shape (none for the infinite plane).
std::optional<Bounds3> shape_box(const AnalyticShape& s) {
  using K = AnalyticShape::Kind;
  const double r = s.radius;
  switch (s.kind) {
    case K::Sphere:
      return Bounds3{{-r, -r, -r}, {r, r, r}};
    case K::Box:
      return Bounds3{-0.5 * s.size, 0.5 * s.size};
    case K::Cylinder:
      return Bounds3{{-r, 0, -r}, {r, s.height, r}};
    case K::Disk:
      return Bounds3{{-r, 0, -r}, {r, 0, r}};
    case K::Rectangle:
      return Bounds3{{-0.5, 0, -0.5}, {0.5, 0, 0.5}};
    case K::Plane:
      break;
  }
  return std::nullopt;
}

// The world bounding box of a top-level geometry (empty for an infinite plane).
Bounds3 record_box(const Accel::Record& rec) {
  using K = Accel::Record::Kind;
  Bounds3 b;
  if (rec.kind == K::Shape && rec.shape) {
    if (auto sb = shape_box(*rec.shape)) b = world_box(*sb, rec.world_from_object);
    return b;
  }
  const auto add = [&](const TriangleMesh& m, const Transform* xf) {
    for (const Vec3f& p : m.positions) {
      const Vec3 q{p.x, p.y, p.z};
      b.extend(xf ? xf->point(q) : q);
    }
  };
  if (rec.kind == K::FlatMesh && rec.mesh) add(*rec.mesh, nullptr);
  if (rec.kind == K::Instance && rec.proto)
    for (const TriangleMesh& m : rec.proto->meshes) add(m, &rec.world_from_object);
  return b;
}

std::vector<Bounds3> object_boxes(const Scene& s) {
  std::vector<Bounds3> boxes;
  std::vector<Bounds3> proto(s.prototypes.size());
  for (size_t i = 0; i < s.prototypes.size(); ++i)
    for (const TriangleMesh& m : s.prototypes[i].meshes)
      for (const Vec3f& p : m.positions) proto[i].extend(Vec3{p.x, p.y, p.z});
  for (const Instance& in : s.instances)
    if (in.prototype < proto.size() && proto[in.prototype].lo.x <= proto[in.prototype].hi.x)
      boxes.push_back(world_box(proto[in.prototype], in.world_from_object));
  for (const AnalyticShape& sh : s.shapes)
    if (auto b = shape_box(sh)) boxes.push_back(world_box(*b, sh.world_from_object));
  return boxes;
}

}  // namespace

std::optional<Editor::RayOverview> Editor::ray_overview(int nu, int nv, int64_t version) {
  RayOverview o;
  o.nu = nu;
  o.nv = nv;
  const bool ok = preview_.with_state(version, 10, [&](const Scene& s, const Renderer&) {
    for (int j = 0; j < nv; ++j)
      for (int i = 0; i < nu; ++i) {
        CameraSample cs;
        cs.uv = {(i + 0.5) / nu, (j + 0.5) / nv};
        const std::optional<CameraRay> r = s.camera->generate(cs);
        o.org.push_back(r ? r->org : Vec3{});
        o.dir.push_back(r ? r->dir : Vec3{});
        o.valid.push_back(r ? 1 : 0);
      }
    o.boxes = object_boxes(s);
  });
  if (!ok) return std::nullopt;
  return o;
}

}  // namespace anamorph::server
