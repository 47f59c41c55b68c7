// `anamorph calib`: the scene camera as a calibration file for OpenCV, COLMAP, Kalibr or as
// anamorph's JSON, and an OpenCV or Kalibr file back as a scene camera (app/calib_formats.h,
// docs/vision.md).
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <filesystem>
#include <stdexcept>

#include "app/calib_formats.h"
#include "app/common.h"
#include "app/output_guard.h"
#include "io/image_io.h"

namespace anamorph::app {

namespace {

namespace fs = std::filesystem;

struct CalibArgs {
  SceneOptions scene;
  std::string format, output, import, image_name = "image.exr";
};

void write_text(const fs::path& file, const std::string& text) {
  AtomicFile f(file);
  f.write(text.data(), text.size());
  f.commit();
}

int run_import(const CalibArgs& a) {
  Calibration c;
  try {
    c = read_calibration(a.import);
  } catch (const std::runtime_error& e) {
    print_error(e.what());
    return kBadInput;
  }
  std::string from = fs::path(a.import).filename().string();
  for (char& ch : from)
    if (static_cast<unsigned char>(ch) < 0x20) ch = '?';
  const std::string toml = camera_toml(c, from);
  if (a.output.empty()) {
    fmt::print("{}", toml);
    return kOk;
  }
  check_outputs({{fs::path(a.import), "--import"}}, {{fs::path(a.output), "-o " + a.output}});
  write_text(a.output, toml);
  return kOk;
}

// The files an export writes (COLMAP's three in the -o directory), each with its option's name
// for errors; the empty list when -o's extension does not fit the format (the error printed).
std::vector<std::pair<fs::path, std::string>> export_outputs(const CalibArgs& a) {
  const fs::path out = a.output;
  const std::string ext = out.extension().string();
  if (a.format == "opencv" && ext != ".yml" && ext != ".yaml" && ext != ".json") {
    print_error(fmt::format("-o {}: an OpenCV FileStorage file is .yml, .yaml or .json", a.output));
    return {};
  }
  if (a.format == "kalibr" && ext != ".yml" && ext != ".yaml") {
    print_error(fmt::format("-o {}: a Kalibr camchain is .yaml or .yml", a.output));
    return {};
  }
  std::vector<std::pair<fs::path, std::string>> outputs;
  if (a.format == "colmap") {
    for (const char* f : {"cameras.txt", "images.txt", "points3D.txt"})
      outputs.emplace_back(out / f, fmt::format("-o {} ({})", a.output, f));
  } else {
    outputs.emplace_back(out, "-o " + a.output);
  }
  return outputs;
}

// Writes the calibration in a.format; kalibr is the Kalibr camchain already made.
int write_calibration(const CalibArgs& a, const Calibration& c, const std::string& kalibr) {
  const fs::path out = a.output;
  if (a.format == "opencv") {
    write_text(out, opencv_text(c, out.extension().string() == ".json"));
  } else if (a.format == "kalibr") {
    write_text(out, kalibr);
  } else if (a.format == "json") {
    write_text(out, calibration_json(c));
  } else {
    if (!fs::is_directory(out)) {
      print_error(
          fmt::format("-o {}: a COLMAP text model is a directory; create it first", a.output));
      return kBadInput;
    }
    write_text(out / "cameras.txt", colmap_cameras(c));
    write_text(out / "images.txt", colmap_images(c, a.image_name));
    write_text(out / "points3D.txt",
               "# 3D point list with one line of data per point:\n"
               "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n"
               "# Number of points: 0, mean track length: 0\n");
  }
  return kOk;
}

int run_calib(const CalibArgs& a) {
  if (!a.import.empty()) {
    if (!a.scene.scene.empty() || !a.format.empty()) {
      print_error("--import takes only a file (and -o for the TOML): no scene or --format");
      return kBadInput;
    }
    return run_import(a);
  }
  if (a.scene.scene.empty() || a.format.empty() || a.output.empty()) {
    print_error("calib needs SCENE, --format and -o (or --import FILE)");
    return kBadInput;
  }
  const std::vector<std::pair<fs::path, std::string>> outputs = export_outputs(a);
  if (outputs.empty()) return kBadInput;
  check_outputs(scene_file_input(a.scene.scene), outputs);
  set_interrupt_note(a.output + " not written");
  const Scene s = load(a.scene);
  check_outputs(s.inputs, outputs);
  Calibration c;
  std::string kalibr;
  try {
    c = calibration_of(s, nullptr);
    if (a.format == "kalibr") kalibr = kalibr_text(c);
  } catch (const NoCalibration& e) {
    print_error(fmt::format(
        "{}: no {} calibration: {}; `anamorph rays {} -o rays.exr` writes the ray of every "
        "pixel instead",
        a.scene.scene, a.format, e.why, a.scene.scene));
    return kBadInput;
  }
  return write_calibration(a, c, kalibr);
}

}  // namespace

void add_calib(CLI::App& app, std::function<int()>& runner) {
  auto a = std::make_shared<CalibArgs>();
  CLI::App* cmd = app.add_subcommand(
      "calib",
      "Write the camera as a calibration (OpenCV FileStorage, COLMAP text model, Kalibr camchain, "
      "JSON) for the presets with such a model, or read an OpenCV or Kalibr file back as a scene "
      "camera (docs/vision.md)");
  a->scene.add_to(*cmd, false);
  cmd->add_option("--format", a->format,
                  "opencv (-o .yml/.yaml/.json), colmap (-o an existing directory: cameras.txt, "
                  "images.txt, points3D.txt), kalibr (-o .yaml/.yml camchain) or json (anamorph's)")
      ->check(CLI::IsMember({"opencv", "colmap", "kalibr", "json"}));
  cmd->add_option("-o,--output", a->output,
                  "Output file (directory for colmap); with --import the TOML (default: stdout)");
  cmd->add_option(
      "--import", a->import,
      "Read an OpenCV FileStorage file (.json, .yml, .yaml) or a Kalibr camchain (.yaml) and "
      "print its scene camera as TOML");
  cmd->add_option("--image-name", a->image_name, "NAME in COLMAP's images.txt")
      ->capture_default_str();
  cmd->callback([a, &runner] { runner = [a] { return run_calib(*a); }; });
}

}  // namespace anamorph::app
