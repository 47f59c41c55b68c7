// `anamorph calib`: the exported OpenCV and COLMAP files reproject world points as the scene
// camera's own inverse map (`anamorph project`, Camera::project) does, through independent code
// (cv2.projectPoints / cv2.fisheye.projectPoints; COLMAP's text format parsed and its models
// applied in numpy: tests/app/calib_check.py); import after export is the identity; cameras
// with no such model and bad files exit 2, named.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "cli_util.h"
#include "run_fixture.h"
#include "scene/scene_loader.h"
#include "test_util.h"

namespace anamorph {
namespace {

namespace fs = std::filesystem;
using test::CliResult;

const char* kPose = "look_from = [0.3, 0.9, 1.5]\nlook_at = [1.3, 1.4, 0.8]\nup = [0.1, 1, 0]\n";

std::string scene(const std::string& camera) {
  return std::string("[image]\nwidth = 64\nheight = 48\n[camera]\n") + kPose + camera;
}

const char* kBrownConrady =
    "preset = \"opencv_pinhole\"\nfx = 50\nfy = 52\ncx = 30.2\ncy = 24.1\nk1 = -0.2\n"
    "k2 = 0.05\np1 = 0.001\np2 = -0.002\nk3 = 0.01\n";
const char* kKannalaBrandt =
    "preset = \"opencv_fisheye\"\nfx = 60\nfy = 61\ncx = 62\ncy = 47.7\nk1 = 0.05\n"
    "k2 = -0.01\nk3 = 0.002\nk4 = -0.0003\ncalibration_size = [128, 96]\n";
const char* kPerspective = "preset = \"perspective\"\nfov = 70\nlens_shift = [0.05, -0.03]\n";
const char* kEquidistant = "preset = \"fisheye\"\nfov = 160\n";

bool have_cv2() {
  return test::run_shell("/usr/bin/python3 -c 'import cv2, numpy, yaml'").code == 0;
}

// World points the camera sees: along rays of a few pixels, at a few distances, less than 85
// degrees off the axis (OpenCV's fisheye model, theta = atan(r), ends at 90).
std::vector<Vec3> seen_points(const Scene& s) {
  std::vector<Vec3> p;
  const Vec3 ahead = normalize(s.camera->rig().vector({0, 0, -1}));
  const Vec2 uv[] = {{0.5, 0.5},   {0.1, 0.2},  {0.85, 0.3}, {0.3, 0.9},
                     {0.95, 0.95}, {0.6, 0.12}, {0.4, 0.6},  {0.62, 0.41}};
  for (size_t i = 0; i < std::size(uv); ++i)
    if (const auto r = s.camera->generate({uv[i]});
        r && dot(normalize(r->dir), ahead) > std::cos(85 * kPi / 180))
      p.push_back(r->org + r->dir * (0.7 + i));
  EXPECT_GE(p.size(), 3u);
  return p;
}

// The checker's pixels for `points` against the scene camera's project(), in pixels.
double worst_difference(const Scene& s, const std::string& kind, const std::string& file) {
  const std::vector<Vec3> pts = seen_points(s);
  std::string cmd = "/usr/bin/python3 " +
                    (test::source_dir() / "tests/app/calib_check.py").string() + " " + kind + " " +
                    file;
  for (const Vec3& p : pts) cmd += fmt::format(" {:.17g},{:.17g},{:.17g}", p.x, p.y, p.z);
  const CliResult r = test::run_shell(cmd);
  EXPECT_EQ(r.code, 0) << cmd << "\n" << r.out;
  std::istringstream in(r.out);
  double worst = 0;
  for (const Vec3& p : pts) {
    double px = NAN, py = NAN;
    in >> px >> py;
    const std::vector<Vec2> uv = s.camera->project(p);
    EXPECT_EQ(uv.size(), 1u);
    if (uv.size() != 1) continue;
    const double ex = uv[0].x * s.render.width, ey = uv[0].y * s.render.height;
    const double d = std::max(std::abs(px - ex), std::abs(py - ey));
    EXPECT_LE(d, 1e-9) << kind << " point " << p.x << "," << p.y << "," << p.z << ": tool (" << px
                       << ", " << py << ") anamorph (" << ex << ", " << ey << ")";
    worst = std::max(worst, d);
  }
  return worst;
}

struct Fixture {
  test::ScratchDir dir{"calib"};
  std::string path(const std::string& name) const { return (dir.dir / name).string(); }
};

TEST(CalibCli, OpenCvAndColmapReprojectAsTheCamera) {
  if (!have_cv2()) GTEST_SKIP() << "/usr/bin/python3 with cv2, numpy and yaml not available";
  Fixture fx;
  const std::pair<const char*, const char*> cams[] = {{"bc", kBrownConrady},
                                                      {"kb", kKannalaBrandt},
                                                      {"persp", kPerspective},
                                                      {"equidistant", kEquidistant}};
  for (const auto& [name, cam] : cams) {
    const std::string file = fx.dir.write(std::string(name) + ".toml", scene(cam));
    const Scene s = load_scene(file);
    for (const char* ext : {".yml", ".json"}) {
      const std::string out = fx.path(std::string(name) + ext);
      const CliResult r = test::run_cli("calib " + file + " --format opencv -o " + out);
      ASSERT_EQ(r.code, 0) << r.out;
      std::printf("%s %s: worst %.3g px\n", name, ext, worst_difference(s, "opencv", out));
    }
    const std::string dir = fx.path(std::string(name) + "_colmap");
    fs::create_directory(dir);
    const CliResult r = test::run_cli("calib " + file + " --format colmap -o " + dir);
    ASSERT_EQ(r.code, 0) << r.out;
    std::printf("%s colmap: worst %.3g px\n", name, worst_difference(s, "colmap", dir));
    if (std::string(name) == "bc") continue;  // (k3: no Kalibr radtan)
    const std::string kalibr = fx.path(std::string(name) + ".yaml");
    const CliResult k = test::run_cli("calib " + file + " --format kalibr -o " + kalibr);
    ASSERT_EQ(k.code, 0) << k.out;
    std::printf("%s kalibr: worst %.3g px\n", name, worst_difference(s, "kalibr", kalibr));
  }
}

// The numbers of an OpenCV JSON file, in order.
std::vector<double> numbers(const std::string& text) {
  std::vector<double> v;
  std::string t = text;
  for (char& c : t)
    if (!(std::isdigit(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == 'e')) c = ' ';
  std::istringstream in(t);
  for (std::string w; in >> w;)
    if (w != "e" && w != "-") v.push_back(std::stod(w));
  return v;
}

TEST(CalibCli, ImportAfterExportIsTheIdentity) {
  Fixture fx;
  for (const char* cam : {kBrownConrady, kKannalaBrandt}) {
    const std::string file = fx.dir.write("a.toml", scene(cam));
    ASSERT_EQ(test::run_cli("calib " + file + " --format opencv -o " + fx.path("a.json")).code, 0);
    const CliResult imp =
        test::run_cli("calib --import " + fx.path("a.json") + " -o " + fx.path("b.toml"));
    ASSERT_EQ(imp.code, 0) << imp.out;
    const CliResult again =
        test::run_cli("calib " + fx.path("b.toml") + " --format opencv -o " + fx.path("b.json"));
    ASSERT_EQ(again.code, 0) << again.out;
    const std::vector<double> a = numbers(test::read_text(fx.path("a.json")));
    const std::vector<double> b = numbers(test::read_text(fx.path("b.json")));
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i)
      EXPECT_NEAR(a[i], b[i], 1e-12 * (1 + std::abs(a[i]))) << "number " << i;
  }
}

// The worst difference in pixels between two cameras' images of the points `a` sees.
double worst_between(const Scene& a, const Scene& b) {
  double worst = 0;
  for (const Vec3& p : seen_points(a)) {
    const std::vector<Vec2> ua = a.camera->project(p), ub = b.camera->project(p);
    EXPECT_EQ(ua.size(), 1u);
    EXPECT_EQ(ub.size(), 1u);
    if (ua.size() != 1 || ub.size() != 1) continue;
    const double d = std::max(std::abs(ua[0].x - ub[0].x) * a.render.width,
                              std::abs(ua[0].y - ub[0].y) * a.render.height);
    EXPECT_LE(d, 1e-9) << "point " << p.x << "," << p.y << "," << p.z;
    worst = std::max(worst, d);
  }
  return worst;
}

// Export in each format that reads back, import: the imported scene camera projects world points
// where the original does (a perspective becomes an opencv_pinhole without distortion).
TEST(CalibCli, ImportOfEachFormatProjectsAsTheExportedCamera) {
  Fixture fx;
  const char* kBrownConradyNoK3 =
      "preset = \"opencv_pinhole\"\nfx = 50\nfy = 52\ncx = 30.2\ncy = 24.1\nk1 = -0.2\n"
      "k2 = 0.05\np1 = 0.001\np2 = -0.002\n";
  const std::pair<const char*, const char*> cams[] = {{"persp", kPerspective},
                                                      {"bc", kBrownConrady},
                                                      {"bc4", kBrownConradyNoK3},
                                                      {"kb", kKannalaBrandt},
                                                      {"equidistant", kEquidistant}};
  const std::pair<const char*, const char*> formats[] = {
      {"opencv", ".yml"}, {"opencv", ".json"}, {"kalibr", ".yaml"}};
  for (const auto& [name, cam] : cams) {
    const std::string file = fx.dir.write(std::string(name) + ".toml", scene(cam));
    const Scene a = load_scene(file);
    for (const auto& [format, ext] : formats) {
      const std::string out = fx.path(std::string(name) + "_" + format + ext);
      const CliResult r =
          test::run_cli(fmt::format("calib {} --format {} -o {}", file, format, out));
      if (std::string(name) == "bc" && std::string(format) == "kalibr") {
        EXPECT_EQ(r.code, 2) << "radtan has no k3: " << r.out;
        EXPECT_CONTAINS(r.out, "k3");
        EXPECT_FALSE(fs::exists(out));
        continue;
      }
      ASSERT_EQ(r.code, 0) << r.out;
      const std::string toml = fx.path(std::string(name) + "_" + format + ext + ".toml");
      const CliResult imp = test::run_cli("calib --import " + out + " -o " + toml);
      ASSERT_EQ(imp.code, 0) << imp.out;
      SCOPED_TRACE(std::string(name) + " via " + format + ext);
      std::printf("%s %s%s: import of export, worst %.3g px\n", name, format, ext,
                  worst_between(a, load_scene(toml)));
    }
  }
}

// A file as OpenCV's calibration samples write it (cv2.FileStorage: image size, flags,
// fisheye_model, camera_matrix, a 5 x 1 distortion_coefficients, no pose): imported, the camera
// projects points as cv2.projectPoints / cv2.fisheye.projectPoints with the file.
TEST(CalibCli, ImportOfOpenCvSampleFilesProjectsAsCv2) {
  if (!have_cv2()) GTEST_SKIP() << "/usr/bin/python3 with cv2, numpy and yaml not available";
  Fixture fx;
  for (const int fisheye : {0, 1}) {
    const std::string yml = fx.path(fmt::format("sample{}.yml", fisheye));
    const std::string dist = fisheye ? "[[0.05], [-0.01], [0.002], [-0.0003]]"
                                     : "[[-0.2], [0.05], [0.001], [-0.002], [0.01]]";
    const CliResult w = test::run_shell(fmt::format(
        "/usr/bin/python3 -c \"import cv2, numpy as np\n"
        "fs = cv2.FileStorage('{}', cv2.FILE_STORAGE_WRITE)\n"
        "fs.write('image_width', 64); fs.write('image_height', 48); fs.write('flags', 0)\n"
        "fs.write('fisheye_model', {})\n"
        "fs.write('camera_matrix', np.array([[30., 0, 31.7], [0, 31, 23.2], [0, 0, 1]]))\n"
        "fs.write('distortion_coefficients', np.array({}))\n"
        "fs.write('avg_reprojection_error', 0.3); fs.release()\"",
        yml, fisheye, dist));
    ASSERT_EQ(w.code, 0) << w.out;
    const std::string toml = fx.path(fmt::format("sample{}.toml", fisheye));
    const CliResult imp = test::run_cli("calib --import " + yml + " -o " + toml);
    ASSERT_EQ(imp.code, 0) << imp.out;
    const Scene s = load_scene(toml);
    std::printf("OpenCV sample file, fisheye_model %d: worst %.3g px\n", fisheye,
                worst_difference(s, "opencv", yml));
  }
}

TEST(CalibCli, BadInputsExit2Named) {
  Fixture fx;
  const std::string eq = fx.dir.write("eq.toml", scene("preset = \"equirectangular\"\n"));
  CliResult r = test::run_cli("calib " + eq + " --format opencv -o " + fx.path("x.yml"));
  EXPECT_EQ(r.code, 2);
  EXPECT_CONTAINS(r.out, "equirectangular");
  EXPECT_CONTAINS(r.out, "anamorph rays");
  EXPECT_FALSE(fs::exists(fx.path("x.yml")));
  const std::string es = fx.dir.write("es.toml", scene("preset = \"fisheye\"\nmapping = "
                                                       "\"equisolid\"\n"));
  r = test::run_cli("calib " + es + " --format colmap -o " + fx.dir.dir.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_CONTAINS(r.out, "fisheye");
  const std::string bc = fx.dir.write("bc.toml", scene(kBrownConrady));
  r = test::run_cli("calib " + bc + " --format opencv -o " + fx.path("x.txt"));
  EXPECT_EQ(r.code, 2);
  EXPECT_CONTAINS(r.out, ".yml");
  r = test::run_cli("calib " + bc + " --format colmap -o " + fx.path("missing"));
  EXPECT_EQ(r.code, 2);
  EXPECT_CONTAINS(r.out, "directory");
  const std::string junk = fx.dir.write("junk.json", "{\"image_width\": 64}");
  r = test::run_cli("calib --import " + junk);
  EXPECT_EQ(r.code, 2);
  EXPECT_CONTAINS(r.out, "image_height");
  const std::string skew = fx.dir.write(
      "skew.json",
      "{\"image_width\": 4, \"image_height\": 4, \"camera_matrix\": {\"type_id\": "
      "\"opencv-matrix\", \"rows\": 3, \"cols\": 3, \"dt\": \"d\", \"data\": [1, 0.5, 2, 0, 1, 2, "
      "0, 0, 1]}}");
  r = test::run_cli("calib --import " + skew);
  EXPECT_EQ(r.code, 2);
  EXPECT_CONTAINS(r.out, "camera_matrix");
  const std::string omni = fx.dir.write(
      "omni.yaml",
      "cam0:\n  camera_model: omni\n  intrinsics: [0.8, 400, 400, 320, 240]\n"
      "  distortion_model: radtan\n  distortion_coeffs: [0, 0, 0, 0]\n  resolution: [640, 480]\n");
  r = test::run_cli("calib --import " + omni);
  EXPECT_EQ(r.code, 2);
  EXPECT_CONTAINS(r.out, "cam0.camera_model");
  const std::string broken = fx.dir.write("broken.yml", "%YAML:1.0\n---\nimage_width: [1, 2\n");
  r = test::run_cli("calib --import " + broken);
  EXPECT_EQ(r.code, 2);
  EXPECT_CONTAINS(r.out, "broken.yml:");
}

}  // namespace
}  // namespace anamorph
