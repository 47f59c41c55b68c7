#include "camera/table_functions.h"

#include <fmt/format.h>

#include <stdexcept>
#include <utility>

#include "camera/org_common.h"
#include "math/input_limits.h"

namespace anamorph {

namespace {

RayTableFileReader g_reader = nullptr;  // set once, by scene/loaders.cpp's static initializer

class TableOrg final : public OrgFunctionLoop<TableOrg> {
 public:
  explicit TableOrg(RayTable t) : t_(std::move(t)) {}
  bool eval(Vec2 uv, SurfaceSample* out) const override {
    clear(out);
    Vec3 second[3];
    if (!t_.eval(uv.x, uv.y, &out->p, &out->dpdu, &out->dpdv, second)) return false;
    out->dpduu = second[0], out->dpduv = second[1], out->dpdvv = second[2];
    return true;
  }

 private:
  RayTable t_;
};

class TableDir final : public DirFunctionLoop<TableDir> {
 public:
  explicit TableDir(RayTable t) : t_(std::move(t)) {}
  bool eval(Vec2 uv, const SurfaceSample&, DirSample* out) const override {
    return t_.eval(uv.x, uv.y, &out->d, &out->dd_du, &out->dd_dv);
  }
  bool reads_org_beyond_first_order() const override { return false; }

 private:
  RayTable t_;
};

RayTableData inline_table(const ParamValues& v) {
  RayTableData d;
  const auto& rows = v.vec3_grid("samples");
  d.height = int(rows.size());
  d.width = rows.empty() ? 0 : int(rows[0].size());
  for (size_t j = 0; j < rows.size(); ++j) {
    if (int(rows[j].size()) != d.width)
      throw ParamError("samples", "samples: row " + std::to_string(j) + " has " +
                                      std::to_string(rows[j].size()) + " samples, row 0 has " +
                                      std::to_string(d.width));
    d.values.insert(d.values.end(), rows[j].begin(), rows[j].end());
  }
  if (v.has("valid")) {
    const auto& m = v.number_grid("valid");
    if (int(m.size()) != d.height)
      throw ParamError("valid", "valid has " + std::to_string(m.size()) + " rows, samples " +
                                    std::to_string(d.height));
    for (size_t j = 0; j < m.size(); ++j) {
      if (int(m[j].size()) != d.width)
        throw ParamError("valid", "valid: row " + std::to_string(j) + " has " +
                                      std::to_string(m[j].size()) + " entries, not " +
                                      std::to_string(d.width));
      for (double x : m[j]) d.valid.push_back(x != 0);
    }
  }
  return d;
}

// What the samples of a table must be beyond finite (RayTable checks that): origins within the
// world (math/input_limits.h; an inline grid's are checked as it is read); a direction of zero
// length is a sample without a ray, as `valid` = 0 would mark it (normalizing it gives no
// direction, and interpolating towards it bends its neighbours' rays).
enum class TableOf { Origins, Directions };
void check_samples(RayTableData& d, TableOf what, const char* key) {
  if (d.values.size() != size_t(d.width) * size_t(d.height)) return;  // (RayTable says so)
  if (what == TableOf::Directions) {
    if (d.valid.empty()) d.valid.assign(d.values.size(), true);
    if (d.valid.size() != d.values.size()) return;
    for (size_t i = 0; i < d.values.size(); ++i)
      if (d.values[i] == Vec3{0, 0, 0}) d.valid[i] = false;
    return;
  }
  for (size_t i = 0; i < d.values.size(); ++i)
    if ((d.valid.empty() || d.valid[i]) && is_finite(d.values[i]) && !within_world(d.values[i]))
      throw ParamError(key,
                       fmt::format("{}: sample ({}, {}) at [{:g}, {:g}, {:g}] lies beyond "
                                   "the {:g} scene units from the origin a ray may start at",
                                   key, i % size_t(d.width), i / size_t(d.width), d.values[i].x,
                                   d.values[i].y, d.values[i].z, kMaxCoordinate));
}

RayTable read_table(const ParamValues& v, const char* default_layer, TableOf what) {
  const bool file = v.has("file"), inline_grid = v.has("samples");
  if (file == inline_grid)
    throw ParamError(file ? "samples" : "file", "give either file or samples (one of them)");
  if (!file && v.has("layer")) throw ParamError("layer", "layer is only used with file");
  if (file && v.has("valid")) throw ParamError("valid", "valid is only used with samples");
  RayTableData data;
  if (file) {
    if (!g_reader)
      throw ParamError("file",
                       "no EXR reader is linked (table files are read by the scene module)");
    try {
      data = g_reader(v.string("file"), v.has("layer") ? v.string("layer") : default_layer);
    } catch (const std::exception& e) {
      throw ParamError("file", e.what());
    }
  } else {
    data = inline_table(v);
  }
  check_samples(data, what, file ? "file" : "samples");
  try {
    return RayTable(data);
  } catch (const std::invalid_argument& e) {
    const char* key = file ? "file" : "samples";
    throw ParamError(key, std::string(key) + ": " + e.what());
  }
}

constexpr const char* kSamplesDoc =
    "Inline grid: rows from the image's top to its bottom, each left to right, one [x, y, z] per "
    "sample; sample (i, j) of a W x H grid sits at the pixel center ((i + 1/2) / W, "
    "(j + 1/2) / H).";
constexpr const char* kValidDoc =
    "With samples: rows of 0 / 1, 0 marking a sample without ray (default: all valid).";
constexpr const char* kFileDoc =
    "An EXR file (relative to the scene file) holding the grid as a layer, as `anamorph rays -o "
    "rays.exr` writes it (layers org, dir, their exact residuals org_lo, dir_lo, and valid).";

const ParamSpec kOrgParams[] = {
    {"file", ParamType::String, "none", kFileDoc},
    {"layer", ParamType::String, "none", "The EXR layer of the origins (default org)."},
    {"samples", ParamType::Vec3Grid, "none", kSamplesDoc},
    {"valid", ParamType::NumberGrid, "none", kValidDoc},
};
const ParamSpec kDirParams[] = {
    {"file", ParamType::String, "none", kFileDoc},
    {"layer", ParamType::String, "none", "The EXR layer of the directions (default dir)."},
    {"samples", ParamType::Vec3Grid, "none", kSamplesDoc},
    {"valid", ParamType::NumberGrid, "none", kValidDoc},
};

std::unique_ptr<OrgFunction> create_org(const ParamValues& v) {
  check_params(kOrgParams, v);
  return std::make_unique<TableOrg>(read_table(v, "org", TableOf::Origins));
}

std::unique_ptr<DirFunction> create_dir(const ParamValues& v) {
  check_params(kDirParams, v);
  return std::make_unique<TableDir>(read_table(v, "dir", TableOf::Directions));
}

}  // namespace

void set_ray_table_file_reader(RayTableFileReader reader) { g_reader = reader; }

const OrgFunctionInfo kTableOrgInfo{
    "table",
    "Ray origins given by samples on a regular grid of pixel centers (a sampled camera: "
    "`anamorph rays` output, a measured or calibrated rig), interpolated by Catmull-Rom bicubics "
    "with analytic derivatives; no ray where the samples around are mostly invalid. The normal is "
    "not "
    "defined (zero): pair it with dir = table or another independent direction.",
    kOrgParams, create_org};
const DirFunctionInfo kTableDirInfo{
    "table",
    "Ray directions given by samples on a regular grid of pixel centers (a measured lens, a "
    "generic per-pixel calibration, or `anamorph rays` output), interpolated by Catmull-Rom "
    "bicubics with analytic derivatives and normalized by the camera; no ray where the samples "
    "around are mostly invalid (their bilinearly interpolated validity is below 1/2). A sample "
    "of zero length counts as invalid.",
    kDirParams, create_dir};

}  // namespace anamorph
