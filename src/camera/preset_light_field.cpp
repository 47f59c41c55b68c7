// Tiled multi-view images: light_field (a quilt of off-axis perspective views for light-field
// displays) and integral (an array of elemental images for integral imaging and holographic
// stereograms). Both are org = TileOrg, one point per tile (constant inside it), and a
// direction set per tile:
//   light_field: dir = focal-plane point - eye, the focal plane shared by every view, so the
//     views converge on it (off-axis frusta, no toe-in);
//   integral:    dir = (x, y, -1) over each lens' field of view, the same for every lens.
#include <algorithm>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "camera/preset_list.h"
#include "camera/preset_util.h"
#include "math/simd.h"

namespace anamorph {

namespace {

struct TileGeometry {
  int cols = 1, rows = 1;
  bool light_field = true;
  // light_field: eye x of each view (index = view number), the focal plane at z = -focus with
  // a window of half extents half_window.
  std::vector<double> eye_x;
  double focus = 1;
  Vec2 half_window;
  // integral: lens pitch, and the half extent of the direction window at z = -1.
  Vec2 pitch, half_field;

  // View number of the tile at (col, row from the top): Looking Glass quilts start at the
  // bottom-left tile and go left to right, then bottom to top.
  int view(int col, int row) const { return (rows - 1 - row) * cols + col; }

  Vec3 origin(int col, int row) const {
    if (light_field) return {eye_x[size_t(view(col, row))], 0, 0};
    return {(col + 0.5 - 0.5 * cols) * pitch.x, (0.5 * rows - row - 0.5) * pitch.y, 0};
  }
  // Direction at tile position st, and its derivatives with respect to s and t.
  Vec3 direction(const Vec3& org, Vec2 st, Vec3* ds, Vec3* dt) const {
    if (light_field) {
      *ds = {2 * half_window.x, 0, 0};
      *dt = {0, -2 * half_window.y, 0};
      return Vec3{(2 * st.x - 1) * half_window.x, (1 - 2 * st.y) * half_window.y, -focus} - org;
    }
    *ds = {2 * half_field.x, 0, 0};
    *dt = {0, -2 * half_field.y, 0};
    return {(2 * st.x - 1) * half_field.x, (1 - 2 * st.y) * half_field.y, -1};
  }
};

// A batch's tiles: the position inside the tile and (kOrigin) the tile's origin (x, y; z is 0),
// as eval computes them. tile_of's floor, clamped, written so that the loops vectorize (one
// lane at a time this was most of the camera's time); the eye table is read by a gather.
struct TileLanes {
  static constexpr int N = kCameraBatch;
  double ox[N], oy[N], s[N], t[N];
};
template <bool kOrigin>
[[gnu::always_inline]] inline void tile_lanes(const TileGeometry& g, const double* __restrict u,
                                              const double* __restrict v, int n,
                                              TileLanes* __restrict out) {
  const int cols = g.cols, rows = g.rows;
  const double last_col = cols - 1, last_row = rows - 1;
  alignas(64) double fx[kCameraBatch], fy[kCameraBatch];
  for (int i = 0; i < n; ++i) {
    const double x = u[i] * cols, y = v[i] * rows;
    // Clamped first, truncation equals floor. Comparisons, not std::max: a NaN position lands
    // in tile 0 (and is rejected by the callers' checks), infinities in the edge tiles. (Selects
    // and conversions in one loop leave GCC with branches.)
    const double cx = x > 0 ? x : 0.0, cy = y > 0 ? y : 0.0;
    fx[i] = cx < last_col ? cx : last_col, fy[i] = cy < last_row ? cy : last_row;
  }
  int col[kCameraBatch], row[kCameraBatch];
  for (int i = 0; i < n; ++i) {
    col[i] = int(fx[i]), row[i] = int(fy[i]);
    out->s[i] = u[i] * cols - col[i], out->t[i] = v[i] * rows - row[i];
  }
  if (!kOrigin) return;
  if (g.light_field) {
    const double* __restrict eye = g.eye_x.data();
    for (int i = 0; i < n; ++i)
      out->ox[i] = eye[(rows - 1 - row[i]) * cols + col[i]], out->oy[i] = 0;
  } else {
    for (int i = 0; i < n; ++i) {
      out->ox[i] = (col[i] + 0.5 - 0.5 * cols) * g.pitch.x;
      out->oy[i] = (0.5 * rows - row[i] - 0.5) * g.pitch.y;
    }
  }
}

// kFirstOrder: only what the finishing pass reads (OrgFunction::eval_batch_first_order); the
// normal and second-derivative fields are zero otherwise.
template <bool kFirstOrder>
[[gnu::always_inline]] inline void tile_org_kernel(const TileGeometry& g, const double* u,
                                                   const double* v, int n, SurfaceBatch* out) {
  with_trip_count<kCameraBatch>(
      n, [&](auto m) __attribute__((always_inline)) {
        TileLanes l;
        tile_lanes<true>(g, u, v, m, &l);
        for (int i = 0; i < m; ++i) {
          out->p[0][i] = l.ox[i], out->p[1][i] = l.oy[i], out->p[2][i] = 0;
          for (int c = 0; c < 3; ++c) out->dpdu[c][i] = out->dpdv[c][i] = 0;
          if (!kFirstOrder)
            for (int c = 0; c < 3; ++c)
              out->n[c][i] = out->dndu[c][i] = out->dndv[c][i] = out->dpduu[c][i] =
                  out->dpduv[c][i] = out->dpdvv[c][i] = 0;
        }
        for (int i = 0; i < m; ++i) out->ok[i] = true;
      });
}
ANAMORPH_KERNEL_BODY void tile_orgs_body(const TileGeometry& g, bool first_order, const double* u,
                                         const double* v, int n, SurfaceBatch* out) {
  if (first_order)
    tile_org_kernel<true>(g, u, v, n, out);
  else
    tile_org_kernel<false>(g, u, v, n, out);
}
constexpr simd::Kernel<tile_orgs_body> tile_orgs;

// TileGeometry::direction for a batch, with the tile origins the origin function gave (before
// coins, which deform the finished rays).
ANAMORPH_KERNEL_BODY void tile_dirs_body(const TileGeometry& geo, const double* u, const double* v,
                                         int n, const SurfaceBatch& org, DirBatch* out) {
  const bool lf = geo.light_field;
  const Vec2 h = lf ? geo.half_window : geo.half_field;
  const double z = lf ? -geo.focus : -1.0, cols = geo.cols, rows = geo.rows;
  with_trip_count<kCameraBatch>(
      n, [&](auto m) __attribute__((always_inline)) {
        TileLanes l;
        tile_lanes<false>(geo, u, v, m, &l);
        for (int i = 0; i < m; ++i) {
          const double x = (2 * l.s[i] - 1) * h.x, y = (1 - 2 * l.t[i]) * h.y;
          out->d[0][i] = lf ? x - org.p[0][i] : x, out->d[1][i] = lf ? y - org.p[1][i] : y;
          out->d[2][i] = lf ? z - org.p[2][i] : z;
          out->du[0][i] = 2 * h.x * cols, out->du[1][i] = 0 * cols, out->du[2][i] = 0 * cols;
          out->dv[0][i] = 0 * rows, out->dv[1][i] = -2 * h.y * rows, out->dv[2][i] = 0 * rows;
        }
        for (int i = 0; i < m; ++i) out->ok[i] = true;
      });
}
constexpr simd::Kernel<tile_dirs_body> tile_dirs;

class TileOrg final : public OrgFunction {
 public:
  explicit TileOrg(const TileGeometry& g) : g_(g) {}
  bool eval(Vec2 uv, SurfaceSample* out) const override {
    return eval_as_batch_of_one(*this, uv, out);
  }
  void eval_batch(const double* u, const double* v, int n, SurfaceBatch* out) const override {
    tile_orgs(g_, false, u, v, n, out);
  }
  void eval_batch_first_order(const double* u, const double* v, int n,
                              SurfaceBatch* out) const override {
    tile_orgs(g_, true, u, v, n, out);
  }

 private:
  TileGeometry g_;
};

class TileDir final : public DirFunction {
 public:
  explicit TileDir(const TileGeometry& g) : g_(g) {}
  bool eval(Vec2 uv, const SurfaceSample& org, DirSample* out) const override {
    return eval_as_batch_of_one(*this, uv, org, out);
  }
  void eval_batch(const double* u, const double* v, int n, const SurfaceBatch& org,
                  DirBatch* out) const override {
    tile_dirs(g_, u, v, n, org, out);
  }
  bool reads_org_beyond_first_order() const override { return false; }  // only p

 private:
  TileGeometry g_;
};

// Image position of tile (col, row) at tile position st, if st lies inside the tile.
bool tile_uv(const TileGeometry& g, int col, int row, Vec2 st, Vec2* uv) {
  if (!(st.x >= -1e-9 && st.x <= 1 + 1e-9 && st.y >= -1e-9 && st.y <= 1 + 1e-9)) return false;
  *uv = {(col + std::clamp(st.x, 0.0, 1.0)) / g.cols, (row + std::clamp(st.y, 0.0, 1.0)) / g.rows};
  return true;
}

// Every tile whose ray passes through q (one per view or lens that sees it).
std::vector<Vec2> tile_project(const TileGeometry& g, const Vec3& q) {
  std::vector<Vec2> out;
  if (!(q.z < 0)) return out;
  Vec2 uv;
  if (g.light_field) {
    for (int row = 0; row < g.rows; ++row)
      for (int col = 0; col < g.cols; ++col) {
        const Vec3 e = g.origin(col, row);
        // The focal-plane point on the line from the eye through q.
        const Vec3 f = e + (q - e) * (g.focus / -q.z);
        const Vec2 st{(f.x / g.half_window.x + 1) / 2, (1 - f.y / g.half_window.y) / 2};
        if (tile_uv(g, col, row, st, &uv)) out.push_back(uv);
      }
    return out;
  }
  // Only lenses within the field of view's footprint can see q.
  const double depth = -q.z;
  const auto col_of = [&](double x) { return x / g.pitch.x + 0.5 * g.cols - 0.5; };
  const auto row_of = [&](double y) { return 0.5 * g.rows - 0.5 - y / g.pitch.y; };
  const int c0 = std::max(0, int(std::floor(col_of(q.x - g.half_field.x * depth))));
  const int c1 = std::min(g.cols - 1, int(std::ceil(col_of(q.x + g.half_field.x * depth))));
  const int r0 = std::max(0, int(std::floor(row_of(q.y + g.half_field.y * depth))));
  const int r1 = std::min(g.rows - 1, int(std::ceil(row_of(q.y - g.half_field.y * depth))));
  for (int row = r0; row <= r1; ++row)
    for (int col = c0; col <= c1; ++col) {
      const Vec3 d = q - g.origin(col, row);
      const Vec2 st{(d.x / depth / g.half_field.x + 1) / 2, (1 - d.y / depth / g.half_field.y) / 2};
      if (tile_uv(g, col, row, st, &uv)) out.push_back(uv);
    }
  return out;
}

VirtualCameraParts tile_parts(const TileGeometry& g, const ParamValues& v, std::string desc) {
  VirtualCameraParts p;
  p.org = std::make_unique<TileOrg>(g);
  p.dir = std::make_unique<TileDir>(g);
  p.world_from_camera = rig_from_look_at(v);
  p.description = std::move(desc);
  p.inverse = make_inverse([g](const Vec3& q) { return tile_project(g, q); });
  return p;
}

// --- light_field -----------------------------------------------------------------------------

const ParamSpec kLightFieldParams[] = {
    ANAMORPH_LOOK_AT_PARAMS,
    {"columns", ParamType::Integer, "8", "Tiles per quilt row.", 1, 1024},
    {"rows", ParamType::Integer, "6", "Quilt rows.", 1, 1024},
    {.name = "view_cone",
     .type = ParamType::Number,
     .default_value = "40",
     .doc = "Angle in degrees between the outermost views, seen from the focal plane's center.",
     .min = 0,
     .max = 180,
     .max_exclusive = true,
     .unit = "degrees"},
    {.name = "fov",
     .type = ParamType::Number,
     .default_value = "14",
     .doc =
         "Vertical field of view of each view in degrees (from the central eye); the focal plane "
         "passes through look_at.",
     .min = 0,
     .max = 180,
     .min_exclusive = true,
     .max_exclusive = true,
     .unit = "degrees"},
};

VirtualCameraParts create_light_field(const ParamValues& v, const ImageInfo& img) {
  check_params(kLightFieldParams, v);
  TileGeometry g;
  g.light_field = true;
  g.cols = int(v.integer("columns")), g.rows = int(v.integer("rows"));
  g.focus = length(v.vec3("look_at") - v.vec3("look_from"));
  const double tile_aspect = (double(img.width) / g.cols) / (double(img.height) / g.rows);
  g.half_window.y = g.focus * std::tan(radians(v.number("fov")) / 2);
  g.half_window.x = g.half_window.y * tile_aspect;
  // View i of n at angle -cone/2 + cone i / (n - 1): view 0 is the leftmost eye.
  const int n = g.cols * g.rows;
  const double cone = radians(v.number("view_cone"));
  for (int i = 0; i < n; ++i) {
    const double a = n > 1 ? -cone / 2 + cone * i / (n - 1) : 0;
    g.eye_x.push_back(g.focus * std::tan(a));
  }
  return tile_parts(g, v,
                    fmt::format("light field quilt {}x{} (org eye per tile + dir toward the "
                                "shared focal plane)",
                                g.cols, g.rows));
}

// --- integral --------------------------------------------------------------------------------

const ParamSpec kIntegralParams[] = {
    ANAMORPH_LOOK_AT_PARAMS,
    {"columns", ParamType::Integer, "32", "Lenses per row (elemental images across).", 1, 100000},
    {"rows", ParamType::Integer, "18", "Rows of lenses.", 1, 100000},
    {.name = "width",
     .type = ParamType::Number,
     .default_value = "1",
     .doc =
         "Width of the lens array in world units, centered on look_from; its height follows from "
         "the image aspect.",
     .min = 0,
     .min_exclusive = true,
     .unit = "scene units"},
    {.name = "lens_fov",
     .type = ParamType::Number,
     .default_value = "40",
     .doc = "Horizontal field of view of each elemental image in degrees.",
     .min = 0,
     .max = 180,
     .min_exclusive = true,
     .max_exclusive = true,
     .unit = "degrees"},
};

VirtualCameraParts create_integral(const ParamValues& v, const ImageInfo& img) {
  check_params(kIntegralParams, v);
  TileGeometry g;
  g.light_field = false;
  g.cols = int(v.integer("columns")), g.rows = int(v.integer("rows"));
  const double w = v.number("width"), h = w / img.aspect();
  g.pitch = {w / g.cols, h / g.rows};
  const double tile_aspect = g.pitch.x / g.pitch.y;
  g.half_field.x = std::tan(radians(v.number("lens_fov")) / 2);
  g.half_field.y = g.half_field.x / tile_aspect;
  return tile_parts(g, v,
                    fmt::format("integral {}x{} lenses (org lens centers + dir elemental "
                                "perspective)",
                                g.cols, g.rows));
}

}  // namespace

const PresetInfo kLightFieldPreset{
    "light_field",
    "A light-field display quilt: columns x rows off-axis perspective views across view_cone, "
    "converging on the focal plane through look_at. View 0 (leftmost eye) is the bottom-left "
    "tile; views go left to right, then bottom to top (Looking Glass order).",
    kLightFieldParams, create_light_field};

const PresetInfo kIntegralPreset{
    "integral",
    "An integral-imaging / holographic-stereogram lens array: columns x rows elemental images, "
    "each a small perspective view from its lens center, un-flipped for display behind the same "
    "lens array.",
    kIntegralParams, create_integral};

}  // namespace anamorph
