// cubemap: six 90-degree perspective faces from one point, laid out in one image.
// org = point, dir = CubemapDir: in face f at face position (s, t) in [0,1]^2 (t downward),
//   dir = axis_f + (2s - 1) right_f + (2t - 1) down_f.
// Face order (both layouts): +X, -X, +Y, -Y, +Z, -Z of camera space (x right, y up, z back; -Z
// is the look_at direction). "3x2": faces 0 1 2 on the top row, 3 4 5 below; "6x1": 0..5 left
// to right.
// convention "inside": every face is the un-mirrored view from the cube's center (side faces
// upright; +Y seen looking up with -Z at its bottom edge, -Y looking down with -Z at its top
// edge). convention "opengl": the faces of OpenGL's cube-map table (sc, tc per major axis), so
// the images load unchanged as GL_TEXTURE_CUBE_MAP_POSITIVE_X.. faces (row 0 = top).
#include <array>
#include <cmath>

#include "camera/cube_faces.h"
#include "camera/org_basic.h"
#include "camera/preset_list.h"
#include "camera/preset_util.h"

namespace anamorph {

namespace {

using Face = CubeFace;
using FaceTable = CubeFaceTable;

// The tables (camera/cube_faces.h).
const FaceTable& kInside = kCubeInside;
const FaceTable& kOpenGl = kCubeOpenGl;

struct CubeGeometry {
  const FaceTable* faces = &kInside;
  int cols = 3, rows = 2;
};

class CubemapDir final : public DirFunctionLoop<CubemapDir> {
 public:
  explicit CubemapDir(const CubeGeometry& g) : g_(g) {}
  bool eval(Vec2 uv, const SurfaceSample&, DirSample* out) const override {
    const TileCoord tc = tile_of(uv, g_.cols, g_.rows);
    const Face& f = (*g_.faces)[size_t(tc.row * g_.cols + tc.col)];
    out->d = f.axis + f.right * (2 * tc.st.x - 1) + f.down * (2 * tc.st.y - 1);
    out->dd_du = f.right * (2.0 * g_.cols);
    out->dd_dv = f.down * (2.0 * g_.rows);
    return true;
  }

 private:
  CubeGeometry g_;
};

std::vector<Vec2> cubemap_project(const CubeGeometry& g, const Vec3& q) {
  std::optional<Vec2> uv = cube_layout_position(*g.faces, g.cols, g.rows, q);
  if (!uv || !clamp_to_image(&*uv)) return {};
  return {*uv};
}

const std::string_view kLayouts[] = {"3x2", "6x1"};
const std::string_view kConventions[] = {"inside", "opengl"};

const ParamSpec kParams[] = {
    ANAMORPH_LOOK_AT_PARAMS,
    {"layout", ParamType::String, "\"3x2\"",
     "Face arrangement, faces in the order +X -X +Y -Y +Z -Z: \"3x2\" (two rows of three) or "
     "\"6x1\" (one row). Square faces need a 3:2 or 6:1 image.",
     -kInf, kInf, kLayouts},
    {"convention", ParamType::String, "\"inside\"",
     "Face orientation: \"inside\" (un-mirrored views from the center) or \"opengl\" (OpenGL's "
     "cube-map table, mirrored when viewed as pictures).",
     -kInf, kInf, kConventions},
};

VirtualCameraParts create(const ParamValues& v, const ImageInfo&) {
  check_params(kParams, v);
  CubeGeometry g;
  g.faces = v.string("convention") == "opengl" ? &kOpenGl : &kInside;
  if (v.string("layout") == "6x1") g.cols = 6, g.rows = 1;
  VirtualCameraParts p;
  p.org = make_point_org({});
  p.dir = std::make_unique<CubemapDir>(g);
  p.world_from_camera = rig_from_look_at(v);
  p.description = "cubemap " + v.string("layout") + " " + v.string("convention") +
                  " (org point + dir six face planes)";
  p.inverse = make_inverse([g](const Vec3& q) { return cubemap_project(g, q); });
  return p;
}

}  // namespace

const PresetInfo kCubemapPreset{
    "cubemap",
    "Six 90-degree faces (+X -X +Y -Y +Z -Z) in a 3x2 or 6x1 layout: org = point, dir = six "
    "face planes.",
    kParams, create};

}  // namespace anamorph
