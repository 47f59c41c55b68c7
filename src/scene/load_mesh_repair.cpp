#include "scene/load_mesh_repair.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <tuple>

#include <fmt/format.h>

#include "scene/loaders.h"

namespace anamorph {

namespace {

Vec3 to_d(const Vec3f& v) { return Vec3(v); }

// Twice the area times the unit normal of triangle t (counter-clockwise front).
Vec3 area_normal(const TriangleMesh& m, size_t t) {
  const Vec3 a = to_d(m.positions[m.indices[3 * t]]);
  const Vec3 b = to_d(m.positions[m.indices[3 * t + 1]]);
  const Vec3 c = to_d(m.positions[m.indices[3 * t + 2]]);
  return cross(b - a, c - a);
}

bool is_degenerate(const TriangleMesh& m, size_t t) {
  const uint32_t i0 = m.indices[3 * t], i1 = m.indices[3 * t + 1], i2 = m.indices[3 * t + 2];
  if (i0 == i1 || i1 == i2 || i0 == i2) return true;
  const Vec3 a = to_d(m.positions[i0]);
  const Vec3 e1 = to_d(m.positions[i1]) - a, e2 = to_d(m.positions[i2]) - a;
  // sin^2 of the corner angle below 1e-20: zero area at float precision (collinear or repeated
  // points), without a threshold that depends on the model's units.
  const double c2 = length_squared(cross(e1, e2));
  return !(c2 > 1e-20 * length_squared(e1) * length_squared(e2));
}

// The errors no repair fixes: counts that disagree, non-finite positions, indices out of range.
void check_mesh_shape(const TriangleMesh& m) {
  const std::string what = fmt::format("mesh '{}'", m.name);
  const size_t n = m.positions.size();
  if (m.indices.size() % 3 != 0)
    throw LoadError(fmt::format("{}: {} indices is not a multiple of 3", what, m.indices.size()));
  if (!m.normals.empty() && m.normals.size() != n)
    throw LoadError(fmt::format("{}: {} normals for {} positions", what, m.normals.size(), n));
  if (!m.uvs.empty() && m.uvs.size() != n)
    throw LoadError(fmt::format("{}: {} uvs for {} positions", what, m.uvs.size(), n));

  const size_t non_finite = size_t(std::count_if(m.positions.begin(), m.positions.end(),
                                                 [](const Vec3f& p) { return !is_finite(p); }));
  if (non_finite > 0)
    throw LoadError(
        fmt::format("{}: positions are non-finite ({} of {} are inf or NaN)", what, non_finite, n));
  for (size_t k = 0; k < m.indices.size(); ++k)
    if (m.indices[k] >= n)
      throw LoadError(fmt::format("{}: index {} (triangle {}) is out of range: {} vertices", what,
                                  m.indices[k], k / 3, n));
}

// Normals made unit; those of no length or not finite replaced by their faces' area-weighted sum.
void repair_normals(TriangleMesh& m, MeshRepairs& repairs) {
  const size_t n = m.positions.size();
  std::vector<uint32_t> bad;
  for (uint32_t v = 0; v < n; ++v) {
    Vec3f& nv = m.normals[v];
    const double len = length(to_d(nv));
    if (std::isfinite(len) && len > 1e-12)
      nv = Vec3f(to_d(nv) / len);
    else
      bad.push_back(v);
  }
  if (bad.empty()) return;
  repairs.bad_normals += bad.size();
  std::vector<Vec3> sum(n);
  for (size_t t = 0; t < m.triangle_count(); ++t) {
    const Vec3 an = area_normal(m, t);
    for (int k = 0; k < 3; ++k) sum[m.indices[3 * t + k]] += an;
  }
  for (uint32_t v : bad) {
    const double len = length(sum[v]);
    // Faces that cancel out (a two-sided sheet) or an unused vertex: any unit vector is as
    // good as another, so pick +z rather than leave a hole.
    m.normals[v] = len > 0 ? Vec3f(sum[v] / len) : Vec3f{0, 0, 1};
  }
}

}  // namespace

void check_mesh(TriangleMesh& m, MeshRepairs& repairs) {
  check_mesh_shape(m);
  // Drop zero-area triangles: they have no normal and only cost intersection time.
  size_t kept = 0;
  for (size_t t = 0; t < m.triangle_count(); ++t) {
    if (is_degenerate(m, t)) continue;
    for (int k = 0; k < 3; ++k) m.indices[3 * kept + k] = m.indices[3 * t + k];
    ++kept;
  }
  repairs.degenerate_triangles += m.triangle_count() - kept;
  m.indices.resize(3 * kept);

  if (!m.normals.empty()) repair_normals(m, repairs);
  for (Vec2f& uv : m.uvs)
    if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) {
      uv = {0, 0};
      ++repairs.bad_uvs;
    }
}

namespace {

// Vertices grouped by exact position (uv seams split vertices but must not split the shading),
// and the faces around each group as compressed rows: faces[start[g] .. start[g + 1]).
struct PositionGroups {
  std::vector<uint32_t> group, start, faces;
  uint32_t count = 0;
};

PositionGroups group_by_position(const TriangleMesh& m) {
  const size_t nv = m.positions.size(), nt = m.triangle_count();
  PositionGroups pg;
  std::vector<uint32_t> order(nv);
  std::iota(order.begin(), order.end(), 0u);
  auto key = [&](uint32_t v) {
    const Vec3f& p = m.positions[v];
    return std::tuple(p.x, p.y, p.z);
  };
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return key(a) < key(b); });
  pg.group.resize(nv);
  for (size_t i = 0; i < nv; ++i) {
    if (i > 0 && key(order[i]) != key(order[i - 1])) ++pg.count;
    pg.group[order[i]] = pg.count;
  }
  ++pg.count;
  pg.start.assign(pg.count + 1, 0);
  pg.faces.resize(3 * nt);
  for (uint32_t idx : m.indices) ++pg.start[pg.group[idx] + 1];
  for (uint32_t g = 0; g < pg.count; ++g) pg.start[g + 1] += pg.start[g];
  std::vector<uint32_t> fill(pg.start.begin(), pg.start.end() - 1);
  for (size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) pg.faces[fill[pg.group[m.indices[3 * t + k]]]++] = uint32_t(t);
  return pg;
}

// The crease test compares each corner's face with every face around its position: quadratic in
// the valence. Around a position shared by more faces than this (none in real models; a fuzzed
// PLY had 16,000 on one point and took seconds) every face is summed, smooth.
constexpr uint32_t kMaxCreaseValence = 1024;

}  // namespace

void generate_normals(TriangleMesh& m, double crease_degrees) {
  const size_t nv = m.positions.size(), nt = m.triangle_count();
  if (nt == 0) {
    m.normals.clear();
    return;
  }
  const PositionGroups pg = group_by_position(m);
  const std::vector<uint32_t>&group = pg.group, &start = pg.start, &faces = pg.faces;
  const uint32_t groups = pg.count;
  std::vector<Vec3> weighted(nt), unit(nt);
  for (size_t t = 0; t < nt; ++t) {
    weighted[t] = area_normal(m, t);
    const double len = length(weighted[t]);
    unit[t] = len > 0 ? weighted[t] / len : Vec3{0, 0, 0};
  }
  const double cos_crease = std::cos(radians(crease_degrees));
  std::vector<Vec3> smooth(groups, Vec3{0, 0, 0});
  for (uint32_t g = 0; g < groups; ++g)
    if (start[g + 1] - start[g] > kMaxCreaseValence)
      for (uint32_t j = start[g]; j < start[g + 1]; ++j) smooth[g] += weighted[faces[j]];
  // The normal of corner k of face t: the faces around its position within the crease angle.
  const auto corner_normal = [&](size_t t, uint32_t g) {
    Vec3 sum{0, 0, 0};
    if (start[g + 1] - start[g] > kMaxCreaseValence) {
      sum = smooth[g];
    } else {
      for (uint32_t j = start[g]; j < start[g + 1]; ++j) {
        const uint32_t f = faces[j];
        if (dot(unit[f], unit[t]) >= cos_crease) sum += weighted[f];
      }
    }
    const double len = length(sum);
    return len > 0 ? Vec3f(sum / len) : Vec3f(unit[t]);
  };
  // New vertices: one per (old vertex, normal); corners with equal normals share one.
  std::vector<std::vector<std::pair<Vec3f, uint32_t>>> variants(nv);
  std::vector<Vec3f> positions, normals;
  std::vector<Vec2f> uvs;
  positions.reserve(nv);
  normals.reserve(nv);
  for (size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = m.indices[3 * t + k];
      const Vec3f n = corner_normal(t, group[v]);
      uint32_t out = UINT32_MAX;
      for (const auto& [vn, idx] : variants[v])
        if (vn == n) out = idx;
      if (out == UINT32_MAX) {
        out = uint32_t(positions.size());
        positions.push_back(m.positions[v]);
        normals.push_back(n);
        if (!m.uvs.empty()) uvs.push_back(m.uvs[v]);
        variants[v].emplace_back(n, out);
      }
      m.indices[3 * t + k] = out;
    }
  m.positions = std::move(positions);
  m.normals = std::move(normals);
  m.uvs = std::move(uvs);
}

void add_repair_warnings(const MeshRepairs& r, const std::string& file,
                         std::vector<std::string>& warnings) {
  if (r.bad_normals > 0)
    warnings.push_back(
        fmt::format("{}: {} zero-length or non-finite normals recomputed from the geometry", file,
                    r.bad_normals));
  if (r.degenerate_triangles > 0)
    warnings.push_back(fmt::format("{}: {} degenerate (zero-area) triangles dropped", file,
                                   r.degenerate_triangles));
  if (r.bad_uvs > 0)
    warnings.push_back(
        fmt::format("{}: {} non-finite texture coordinates set to (0, 0)", file, r.bad_uvs));
}

}  // namespace anamorph
