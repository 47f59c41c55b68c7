// Mesh origin function. Texture space is covered by a uniform grid of cells listing the
// triangles whose UV bounding box overlaps them, so locating (u, v) costs one cell's triangles.
// Each triangle precomputes its UV-to-barycentric map and the (constant) derivatives of position
// and interpolated normal with respect to texture coordinates.
#include "camera/org_mesh.h"

#include <algorithm>
#include <cmath>

#include "camera/org_common.h"

namespace anamorph {

namespace {

struct UvTriangle {
  Vec2 uv0;
  double m00, m01, m10, m11;  // (b1, b2) = M (uv - uv0)
  Vec3 p0, e1, e2;            // p = p0 + b1 e1 + b2 e2
  Vec3 dpds, dpdt;            // derivatives of p with respect to texture (s, t)
  Vec3 n0, dn1, dn2;          // unnormalized normal N = n0 + b1 dn1 + b2 dn2
  Vec3 dNds, dNdt;
};

class MeshOrg final : public OrgFunctionLoop<MeshOrg> {
 public:
  MeshOrg(std::vector<UvTriangle> tris, ParamRange ur, ParamRange vr, bool flip)
      : tris_(std::move(tris)), ur_(ur), vr_(vr), flip_(flip) {
    build_grid();
  }

  bool eval(Vec2 uv, SurfaceSample* out) const override {
    const double s = ur_(uv.x), t = vr_(uv.y);
    if (!(s >= lo_.x && s <= hi_.x && t >= lo_.y && t <= hi_.y)) return false;
    const int cx = std::min(nx_ - 1, int((s - lo_.x) * inv_cell_.x));
    const int cy = std::min(ny_ - 1, int((t - lo_.y) * inv_cell_.y));
    const size_t cell = size_t(cy) * size_t(nx_) + size_t(cx);
    constexpr double kEps = 1e-10;  // closes cracks between neighbours from rounding
    for (uint32_t k = cell_start_[cell]; k < cell_start_[cell + 1]; ++k) {
      const UvTriangle& tr = tris_[cell_tris_[k]];
      const double ds = s - tr.uv0.x, dt = t - tr.uv0.y;
      const double b1 = tr.m00 * ds + tr.m01 * dt, b2 = tr.m10 * ds + tr.m11 * dt;
      if (b1 < -kEps || b2 < -kEps || b1 + b2 > 1 + kEps) continue;
      clear(out);
      const double su = ur_.scale(), sv = vr_.scale();
      out->p = tr.p0 + tr.e1 * b1 + tr.e2 * b2;
      out->dpdu = tr.dpds * su;
      out->dpdv = tr.dpdt * sv;
      set_normal(tr.n0 + tr.dn1 * b1 + tr.dn2 * b2, tr.dNds, tr.dNdt, su, sv, flip_, out);
      return true;
    }
    return false;
  }

 private:
  void build_grid() {
    lo_ = {kInf, kInf};
    hi_ = {-kInf, -kInf};
    for (const auto& tr : tris_)
      for (const Vec2 c : corners(tr)) {
        lo_ = {std::min(lo_.x, c.x), std::min(lo_.y, c.y)};
        hi_ = {std::max(hi_.x, c.x), std::max(hi_.y, c.y)};
      }
    // About two triangles per cell, in proportion to the UV box's sides.
    const double w = std::max(hi_.x - lo_.x, 1e-12), h = std::max(hi_.y - lo_.y, 1e-12);
    const double cells = std::clamp(double(tris_.size()) / 2, 1.0, 4.0e6);
    nx_ = std::clamp(int(std::sqrt(cells * w / h)), 1, 4096);
    ny_ = std::clamp(int(cells / nx_), 1, 4096);
    inv_cell_ = {nx_ / w, ny_ / h};
    const auto cell_range = [&](const UvTriangle& tr, int* x0, int* x1, int* y0, int* y1) {
      double a = kInf, b = -kInf, c = kInf, d = -kInf;
      for (const Vec2 q : corners(tr)) {
        a = std::min(a, q.x), b = std::max(b, q.x), c = std::min(c, q.y), d = std::max(d, q.y);
      }
      *x0 = std::clamp(int((a - lo_.x) * inv_cell_.x), 0, nx_ - 1);
      *x1 = std::clamp(int((b - lo_.x) * inv_cell_.x), 0, nx_ - 1);
      *y0 = std::clamp(int((c - lo_.y) * inv_cell_.y), 0, ny_ - 1);
      *y1 = std::clamp(int((d - lo_.y) * inv_cell_.y), 0, ny_ - 1);
    };
    // Two passes (count, then fill) into compressed rows.
    std::vector<uint32_t> count(size_t(nx_) * size_t(ny_) + 1, 0);
    int x0, x1, y0, y1;
    for (const auto& tr : tris_) {
      cell_range(tr, &x0, &x1, &y0, &y1);
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) ++count[size_t(y) * size_t(nx_) + size_t(x) + 1];
    }
    for (size_t i = 1; i < count.size(); ++i) count[i] += count[i - 1];
    cell_start_ = count;
    cell_tris_.resize(count.back());
    for (uint32_t k = 0; k < tris_.size(); ++k) {
      cell_range(tris_[k], &x0, &x1, &y0, &y1);
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) cell_tris_[count[size_t(y) * size_t(nx_) + size_t(x)]++] = k;
    }
  }

  static std::array<Vec2, 3> corners(const UvTriangle& tr) {
    // Invert M to recover the UV edges: [e1uv e2uv] = M^-1.
    const double det = tr.m00 * tr.m11 - tr.m01 * tr.m10;
    const Vec2 a{tr.m11 / det, -tr.m10 / det}, b{-tr.m01 / det, tr.m00 / det};
    return {tr.uv0, tr.uv0 + a, tr.uv0 + b};
  }

  std::vector<UvTriangle> tris_;
  ParamRange ur_, vr_;
  bool flip_;
  Vec2 lo_, hi_, inv_cell_;
  int nx_ = 1, ny_ = 1;
  std::vector<uint32_t> cell_start_, cell_tris_;
};

const ParamSpec kParams[] = {
    {"file", ParamType::String, "",
     "Mesh file (glTF, OBJ, PLY, ... ; relative to the scene file). Every mesh with texture "
     "coordinates is used, placed by the file's node transforms."},
    {"select", ParamType::String, "none",
     "Use only the meshes whose mesh, group or node name equals this."},
    {"u_range", ParamType::Vec2, "[0, 1]",
     "Texture coordinate u across the image, left to right (reversed if decreasing)."},
    {"v_range", ParamType::Vec2, "[0, 1]",
     "Texture coordinate v across the image, top to bottom (texture space has v = 0 at the "
     "top, as for images)."},
    kFlipNormalParam,
};

MeshFileReader g_reader = nullptr;  // set once, by scene/loaders.cpp's static initializer

std::unique_ptr<OrgFunction> create(const ParamValues& v) {
  check_params(kParams, v);
  if (!g_reader)
    throw ParamError("file", "no model loader is linked (mesh files are read by the scene module)");
  std::vector<Prototype> prototypes;
  std::vector<Instance> instances;
  try {
    g_reader(v.string("file"), &prototypes, &instances);
  } catch (const std::exception& e) {
    throw ParamError("file", e.what());
  }
  return make_mesh_org(prototypes, instances, v.has("select") ? v.string("select") : std::string(),
                       read_range(v, "u_range"), read_range(v, "v_range"),
                       v.boolean("flip_normal"));
}

}  // namespace

void set_mesh_file_reader(MeshFileReader reader) { g_reader = reader; }

std::unique_ptr<OrgFunction> make_mesh_org(std::span<const Prototype> prototypes,
                                           std::span<const Instance> instances,
                                           const std::string& select, ParamRange ur, ParamRange vr,
                                           bool flip_normal) {
  std::vector<UvTriangle> tris;
  size_t meshes = 0, with_uv = 0;
  for (const Instance& inst : instances) {
    if (inst.prototype >= prototypes.size()) continue;
    const Prototype& proto = prototypes[inst.prototype];
    const Transform& t = inst.world_from_object;
    for (const TriangleMesh& m : proto.meshes) {
      if (!select.empty() && select != m.name && select != proto.name && select != inst.name)
        continue;
      ++meshes;
      if (m.uvs.size() != m.positions.size()) continue;
      ++with_uv;
      const bool has_n = m.normals.size() == m.positions.size();
      for (size_t k = 0; k + 2 < m.indices.size(); k += 3) {
        const uint32_t i0 = m.indices[k], i1 = m.indices[k + 1], i2 = m.indices[k + 2];
        const Vec2 a{m.uvs[i0].x, m.uvs[i0].y}, b{m.uvs[i1].x, m.uvs[i1].y},
            c{m.uvs[i2].x, m.uvs[i2].y};
        const Vec2 ea = b - a, eb = c - a;
        const double det = ea.x * eb.y - ea.y * eb.x;
        if (!(std::abs(det) > 1e-14)) continue;  // no area in texture space: never hit
        UvTriangle tr;
        tr.uv0 = a;
        tr.m00 = eb.y / det, tr.m01 = -eb.x / det, tr.m10 = -ea.y / det, tr.m11 = ea.x / det;
        const Vec3 p0 = t.point(Vec3(m.positions[i0])), p1 = t.point(Vec3(m.positions[i1])),
                   p2 = t.point(Vec3(m.positions[i2]));
        tr.p0 = p0, tr.e1 = p1 - p0, tr.e2 = p2 - p0;
        tr.dpds = tr.e1 * tr.m00 + tr.e2 * tr.m10;
        tr.dpdt = tr.e1 * tr.m01 + tr.e2 * tr.m11;
        Vec3 n0, n1, n2;
        if (has_n) {
          n0 = normalize(t.normal(Vec3(m.normals[i0])));
          n1 = normalize(t.normal(Vec3(m.normals[i1])));
          n2 = normalize(t.normal(Vec3(m.normals[i2])));
        } else {
          const Vec3 object_n = cross(Vec3(m.positions[i1] - m.positions[i0]),
                                      Vec3(m.positions[i2] - m.positions[i0]));
          n0 = n1 = n2 = normalize(t.normal(object_n));
        }
        if (!is_finite(n0) || !is_finite(n1) || !is_finite(n2)) continue;
        tr.n0 = n0, tr.dn1 = n1 - n0, tr.dn2 = n2 - n0;
        tr.dNds = tr.dn1 * tr.m00 + tr.dn2 * tr.m10;
        tr.dNdt = tr.dn1 * tr.m01 + tr.dn2 * tr.m11;
        tris.push_back(tr);
      }
    }
  }
  if (!select.empty() && meshes == 0)
    throw ParamError("select", "no mesh, group or node named '" + select + "' in the file");
  if (tris.empty())
    throw ParamError("file", with_uv == 0 ? "the model has no mesh with texture coordinates"
                                          : "the model's texture coordinates cover no area");
  return std::make_unique<MeshOrg>(std::move(tris), ur, vr, flip_normal);
}

const OrgFunctionInfo kMeshOrgInfo{
    "mesh",
    "A triangle mesh's UV layout (as Arnold's uv_camera, POV-Ray's mesh_camera): the origin at "
    "(u, v) is the surface point with those texture coordinates, with the interpolated shading "
    "normal. With dir = normal (flip = true) it bakes what the surface sees into texture space. "
    "No ray where no triangle covers (u, v); where UV islands overlap, the first triangle "
    "wins.",
    kParams, create};

}  // namespace anamorph
