#include "solve/goals.h"

#include <fmt/format.h>

#include <Eigen/Dense>

#include <cmath>
#include <limits>

#include "scene/shape.h"
#include "scene/toml_reader.h"

namespace anamorph::solve {

namespace {

constexpr double kUnseen = std::numeric_limits<double>::infinity();

// The centre of the world bounding box of the object named `name` (a shape or a mesh instance).
Vec3 object_centre(const Scene& s, const std::string& name, const std::string& where) {
  std::vector<Bounds3> found;
  for (const AnalyticShape& sh : s.shapes) {
    if (sh.name != name) continue;
    const Bounds3 ob = shape_object_bounds(sh);
    Bounds3 b;
    for (int k = 0; k < 8; ++k)
      b.extend(sh.world_from_object.point(
          {k & 1 ? ob.hi.x : ob.lo.x, k & 2 ? ob.hi.y : ob.lo.y, k & 4 ? ob.hi.z : ob.lo.z}));
    found.push_back(b);
  }
  for (const Instance& in : s.instances) {
    if (in.name != name) continue;
    Bounds3 b;
    for (const TriangleMesh& m : s.prototypes[in.prototype].meshes)
      for (const Vec3f& p : m.positions)
        b.extend(in.world_from_object.point({double(p.x), double(p.y), double(p.z)}));
    found.push_back(b);
  }
  const std::string key = where + ".object";
  if (found.empty()) throw SceneError({s.path, 0, 0}, key, fmt::format("no object \"{}\"", name));
  if (found.size() > 1)
    throw SceneError({s.path, 0, 0}, key,
                     fmt::format("{} objects are named \"{}\"", found.size(), name));
  if (found[0].empty())
    throw SceneError({s.path, 0, 0}, key, fmt::format("object \"{}\" is empty", name));
  return found[0].center();
}

// The image position of `p` nearest to `near` (false when the camera does not see p); `seeded`:
// as found from `near` (Camera::project_near: a camera whose inverse is a search looks there
// first, so that a solver step costs little; the report measures with the whole search).
bool seen_at(const Camera& cam, const Vec3& p, Vec2 near, Vec2* uv, bool seeded = false) {
  const std::vector<Vec2> all = seeded ? cam.project_near(p, near) : cam.project(p);
  if (all.empty()) return false;
  *uv = all[0];
  for (const Vec2& q : all)
    if (length(q - near) < length(*uv - near)) *uv = q;
  return true;
}

// The beam's footprint |dP/du x dP/dv| at distance t along the ray at `uv` (0: no ray).
double footprint(const Camera& cam, Vec2 uv, double t) {
  CameraSample cs;
  cs.uv = uv;
  const std::optional<CameraRay> r = cam.generate(cs);
  if (!r) return 0;
  return length(cross(r->dorg_du + r->ddir_du * t, r->dorg_dv + r->ddir_dv * t));
}

// The unit eigenvector of the smallest eigenvalue of the symmetric matrix `m`.
Eigen::Vector2d least_axis(const Eigen::Matrix2d& m) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(m);
  return es.eigenvectors().col(0);  // eigenvalues ascending
}

// Signed distances of the image points `p` (pixels) from the line fitted to them (total least
// squares), oriented by the chord from the first point to the last so that the sign does not
// flip between nearby cameras.
void line_distances(const std::vector<Vec2>& p, double* r) {
  Vec2 c{0, 0};
  for (const Vec2& q : p) c = c + q;
  c = c * (1.0 / double(p.size()));
  Eigen::Matrix2d m = Eigen::Matrix2d::Zero();
  for (const Vec2& q : p) {
    const Eigen::Vector2d d(q.x - c.x, q.y - c.y);
    m += d * d.transpose();
  }
  Eigen::Vector2d n = least_axis(m);
  const Vec2 chord = p.back() - p.front();
  if (n.x() * -chord.y + n.y() * chord.x < 0) n = -n;
  for (size_t i = 0; i < p.size(); ++i) r[i] = n.x() * (p[i].x - c.x) + n.y() * (p[i].y - c.y);
}

// Distances of the image points `p` (pixels) from the circle about `centre` (pixels) through
// them: |p - centre| minus its mean over the points.
void circle_distances(const std::vector<Vec2>& p, Vec2 centre, double* r) {
  double mean = 0;
  for (const Vec2& q : p) mean += length(q - centre);
  mean /= double(p.size());
  for (size_t i = 0; i < p.size(); ++i) r[i] = length(p[i] - centre) - mean;
}

// F = (p - org) x dir of a ray and its derivative along (dorg, ddir).
Vec3 off_ray(const Vec3& p, const CameraRay& r) { return cross(p - r.org, r.dir); }
Vec3 off_ray_d(const Vec3& p, const CameraRay& r, const Vec3& dorg, const Vec3& ddir) {
  return cross(-dorg, r.dir) + cross(p - r.org, ddir);
}

}  // namespace

namespace {

// duv/dk from F's derivative fk = dF/dk at uv (the normal equations of [fu fv] duv = -fk).
bool solve_position(const CameraRay& r, const Vec3& p, const Vec3& fk, Vec2* duv_dk) {
  const Vec3 fu = off_ray_d(p, r, r.dorg_du, r.ddir_du);
  const Vec3 fv = off_ray_d(p, r, r.dorg_dv, r.ddir_dv);
  // The normal equations of [fu fv] duv = -fk.
  const double a = dot(fu, fu), b = dot(fu, fv), c = dot(fv, fv);
  const double det = a * c - b * b;
  if (!(det > 1e-24 * a * c) || !std::isfinite(det)) return false;
  const double gu = -dot(fu, fk), gv = -dot(fv, fk);
  *duv_dk = {(c * gu - b * gv) / det, (a * gv - b * gu) / det};
  return std::isfinite(duv_dk->x) && std::isfinite(duv_dk->y);
}

}  // namespace

bool image_position_derivative(const Camera& cam, const Camera& minus, const Camera& plus,
                               double step, const Vec3& p, Vec2 uv, Vec2* duv_dk) {
  CameraSample cs;
  cs.uv = uv;
  const std::optional<CameraRay> r = cam.generate(cs), lo = minus.generate(cs),
                                 hi = plus.generate(cs);
  if (!r || !lo || !hi || !(step > 0)) return false;
  return solve_position(*r, p, (off_ray(p, *hi) - off_ray(p, *lo)) * (1 / step), duv_dk);
}

bool image_position_derivative(const Camera& cam, const Vec3& p, Vec2 uv, const Vec3& dorg,
                               const Vec3& ddir, Vec2* duv_dk) {
  CameraSample cs;
  cs.uv = uv;
  const std::optional<CameraRay> r = cam.generate(cs);
  return r && solve_position(*r, p, off_ray_d(p, *r, dorg, ddir), duv_dk);
}

Goals::Goals(const CameraGoals& goals, const Scene& loaded, const Camera& start, int width,
             int height)
    : width_(width), height_(height) {
  for (const CameraConstraint& c : goals.constraints) {
    Item it{c, {}, {}, {}, {}, {}};
    const ParamValues& v = c.values;
    if (c.kind == "pin" || c.kind == "magnification")
      it.point =
          v.has("point") ? v.vec3("point") : object_centre(loaded, v.string("object"), c.where);
    if (c.kind == "pin") it.uv = v.vec2("uv");
    if (c.kind == "size" || c.kind == "straight") it.point = v.vec3("from"), it.to = v.vec3("to");
    if (c.kind == "straight") {
      const int n = int(v.integer("samples"));
      for (int k = 0; k < n; ++k)
        it.samples.push_back(it.point + (it.to - it.point) * (k / (n - 1.0)));
    }
    if (c.kind == "keep") {
      const int n = int(v.integer("samples"));
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          CameraSample cs;
          cs.uv = {(i + 0.5) / n, (j + 0.5) / n};
          const std::optional<CameraRay> r = start.generate(cs);
          if (!r) continue;
          it.samples.push_back(r->org + r->dir * v.number("distance"));
          it.at.push_back(cs.uv);
        }
    }
    items_.push_back(std::move(it));
  }
}

int Goals::residual_count(size_t i) const {
  const std::string& k = items_[i].c.kind;
  if (k == "pin") return 2;
  if (k == "keep") return 2 * int(items_[i].samples.size());
  if (k == "straight") return int(items_[i].samples.size());
  return 1;
}

bool Goals::needs_plain() const {
  for (const Item& it : items_)
    if (it.c.kind == "magnification") return true;
  return false;
}

std::vector<Vec3> Goals::points(size_t i) const {
  const Item& it = items_[i];
  const std::string& k = it.c.kind;
  if (k == "pin" || k == "magnification") return {it.point};
  if (k == "size") return {it.point, it.to};
  return it.samples;  // keep, straight
}

const char* Goals::unit(size_t i) const {
  const std::string& k = items_[i].c.kind;
  return k == "pin" || k == "keep" || k == "straight" ? "px" : "%";
}

std::vector<Vec2> Goals::positions(size_t i, const Camera& cam, bool exact) const {
  const Item& it = items_[i];
  const std::string& k = it.c.kind;
  const Vec2 none{kUnseen, kUnseen};
  std::vector<Vec2> uv(points(i).size(), none);
  if (k == "pin" || k == "keep") {
    for (size_t j = 0; j < uv.size(); ++j) {
      const Vec2 near = k == "pin" ? it.uv : it.at[j];
      if (!seen_at(cam, k == "pin" ? it.point : it.samples[j], near, &uv[j], !exact)) uv[j] = none;
    }
    return uv;
  }
  // size, straight: each point found near the one before (the first near the centre).
  Vec2 near{0.5, 0.5};
  const std::vector<Vec3> p = points(i);
  for (size_t j = 0; j < p.size(); ++j) {
    if (!seen_at(cam, p[j], near, &uv[j])) return std::vector<Vec2>(p.size(), none);
    near = uv[j];
  }
  return uv;
}

void Goals::residuals(size_t i, const CameraPair& cp, double* r, bool exact) const {
  residuals_at(i, cp, positions(i, *cp.camera, exact), r);
}

void Goals::residuals_at(size_t i, const CameraPair& cp, const std::vector<Vec2>& uvs,
                         double* r) const {
  const Item& it = items_[i];
  const double w = width_, h = height_;
  // Not seen: a constant penalty of two image widths (the solver moves back toward seeing it).
  const double unseen = 2 * std::max(w, h);
  const auto seen = [](Vec2 uv) { return std::isfinite(uv.x); };
  if (it.c.kind == "pin" || it.c.kind == "keep") {
    for (size_t k = 0; k < uvs.size(); ++k) {
      const Vec2 to = it.c.kind == "pin" ? it.uv : it.at[k];
      r[2 * k] = seen(uvs[k]) ? (uvs[k].x - to.x) * w : unseen;
      r[2 * k + 1] = seen(uvs[k]) ? (uvs[k].y - to.y) * h : unseen;
    }
  } else if (it.c.kind == "size") {
    const Vec2 a = uvs[0], b = uvs[1];
    const double len = std::hypot((a.x - b.x) * w, (a.y - b.y) * h) / w;
    r[0] = seen(a) && seen(b) ? 100 * (len / it.c.values.number("fraction") - 1) : 100;
  } else if (it.c.kind == "magnification") {
    r[0] = seen(uvs[0]) ? magnification_residual(it, cp, uvs[0]) : 100;
  } else {  // straight
    std::vector<Vec2> px;
    for (const Vec2& uv : uvs) px.push_back({uv.x * w, uv.y * h});
    if (!seen(uvs[0])) {
      for (size_t k = 0; k < uvs.size(); ++k) r[k] = unseen;
    } else if (it.c.values.string("shape") == "circle") {
      const Vec2 c = it.c.values.vec2("center");
      circle_distances(px, {c.x * w, c.y * h}, r);
    } else {
      line_distances(px, r);
    }
  }
}

// The local magnification at `uv` (where the point is seen) relative to the camera without
// coins, in percent of its target: from the ray differentials alone (no inverse map).
double Goals::magnification_residual(const Item& it, const CameraPair& cp, Vec2 uv) const {
  CameraSample cs;
  cs.uv = uv;
  const std::optional<CameraRay> ray = cp.camera->generate(cs);
  if (!ray) return 100;
  const double t = dot(it.point - ray->org, ray->dir);
  const double a = footprint(*cp.camera, uv, t), ref = footprint(*cp.plain, uv, t);
  const double m = a > 0 && ref > 0 ? std::sqrt(ref / a) : 0;
  return 100 * (m / it.c.values.number("magnification") - 1);
}

bool Goals::moves_at_fixed_positions(size_t i) const { return items_[i].c.kind == "magnification"; }

double Goals::measure(size_t i, const CameraPair& cam) const {
  std::vector<double> r(size_t(residual_count(i)));
  residuals(i, cam, r.data(), true);
  const Item& it = items_[i];
  const double unseen = 2 * std::max(width_, height_);
  double m = 0;
  if (it.c.kind == "pin" || it.c.kind == "keep") {
    for (size_t k = 0; k + 1 < r.size(); k += 2) {
      if (r[k] == unseen && r[k + 1] == unseen) return kUnseen;
      m = std::max(m, std::hypot(r[k], r[k + 1]));
    }
    return m;
  }
  if (it.c.kind == "straight") {
    for (double x : r) {
      if (x == unseen) return kUnseen;
      m = std::max(m, std::abs(x));
    }
    return m;
  }
  return std::abs(r[0]);
}

}  // namespace anamorph::solve
