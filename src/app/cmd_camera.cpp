// `anamorph rays` and `anamorph project`: the camera's ray field and its inverse map.
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <cmath>
#include <filesystem>
#include <sstream>

#include "app/common.h"
#include "app/output_guard.h"
#include "io/image_io.h"

namespace anamorph::app {

namespace {

struct RaysArgs {
  SceneOptions scene;
  std::string output;
};

// Every pixel centre's ray as CSV rows, streamed a row at a time: a 30000 x 30000 table is
// 80 GB, never held in memory.
void write_rays_csv(const std::filesystem::path& out, const Scene& s) {
  const int W = s.render.width, H = s.render.height;
  AtomicFile file(out);
  std::string row = "px,py,u,v,ox,oy,oz,dx,dy,dz,valid\n";
  for (int y = 0; y < H; ++y) {
    for (int x = 0; x < W; ++x) {
      const Vec2 uv{(x + 0.5) / W, (y + 0.5) / H};
      const auto r = s.camera->generate({uv});
      if (r)
        fmt::format_to(std::back_inserter(row),
                       "{},{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},1\n",
                       x, y, uv.x, uv.y, r->org.x, r->org.y, r->org.z, r->dir.x, r->dir.y,
                       r->dir.z);
      else
        fmt::format_to(std::back_inserter(row), "{},{},{:.17g},{:.17g},0,0,0,0,0,0,0\n", x, y, uv.x,
                       uv.y);
    }
    file.write(row.data(), row.size());
    row.clear();
  }
  file.commit();
}

// Every pixel centre's ray as EXR layers: org and dir as floats, and org_lo, dir_lo the float
// residuals: hi + lo carries each double to about 1e-15 (EXR has no 64-bit floats), which the
// table camera reads back.
void write_rays_exr(const std::filesystem::path& out, const Scene& s) {
  const int W = s.render.width, H = s.render.height;
  OutputImage img;
  img.width = W;
  img.height = H;
  ImageLayer org{"org", {"X", "Y", "Z"}, {}}, dir{"dir", {"X", "Y", "Z"}, {}},
      org_lo{"org_lo", {"X", "Y", "Z"}, {}}, dir_lo{"dir_lo", {"X", "Y", "Z"}, {}},
      valid{"valid", {"V"}, {}};
  const auto put = [](ImageLayer& hi, ImageLayer& lo, double x) {
    const float h = float(x);
    hi.data.push_back(h);
    lo.data.push_back(float(x - double(h)));
  };
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const auto r = s.camera->generate({{(x + 0.5) / W, (y + 0.5) / H}});
      const Vec3 o = r ? r->org : Vec3{}, d = r ? r->dir : Vec3{};
      for (int k = 0; k < 3; ++k) {
        put(org, org_lo, o[k]);
        put(dir, dir_lo, d[k]);
      }
      valid.data.push_back(r ? 1.0f : 0.0f);
    }
  img.layers = {std::move(org), std::move(dir), std::move(org_lo), std::move(dir_lo),
                std::move(valid)};
  img.metadata["anamorph.command"] = command_line();
  img.metadata["anamorph.camera"] = s.camera->describe() + "\n" + s.camera_toml;
  write_exr(out, img);
}

int run_rays(const RaysArgs& a) {
  namespace fs = std::filesystem;
  const fs::path out = a.output;
  // (A device or pipe without an extension, `-o /dev/stdout`, gets CSV.)
  const std::string ext =
      out.extension().empty() && written_directly(out) ? ".csv" : out.extension().string();
  if (ext != ".csv" && ext != ".exr") {
    print_error(fmt::format("-o {}: use .csv or .exr", a.output));
    return kBadInput;
  }
  const std::vector<std::pair<fs::path, std::string>> outputs{{out, "-o " + a.output}};
  check_outputs(scene_file_input(a.scene.scene), outputs);
  set_interrupt_note(a.output + " not written");
  const Scene s = load(a.scene);
  check_outputs(s.inputs, outputs);
  if (ext == ".csv")
    write_rays_csv(out, s);
  else
    write_rays_exr(out, s);
  return kOk;
}

struct ProjectArgs {
  SceneOptions scene;
  std::string point;
  bool json = false;
  int frame = 0;
};

int run_project(const ProjectArgs& a) {
  Vec3 p;
  {
    std::string t = a.point;
    for (char& c : t)
      if (c == ',') c = ' ';
    std::istringstream is(t);
    if (!(is >> p.x >> p.y >> p.z) || !is_finite(p)) {
      print_error(fmt::format("--point {}: expected X,Y,Z (three finite numbers)", a.point));
      return kBadInput;
    }
  }
  const Scene s = load(a.scene, {}, a.frame);
  const std::vector<Vec2> seen = s.camera->project(p);
  if (a.json) {  // every digit (a double round-trips), for tests and tools; the text form has 6
    std::string list;
    for (const Vec2& uv : seen)
      list += fmt::format("{}[{:.17g}, {:.17g}]", list.empty() ? "" : ", ", uv.x * s.render.width,
                          uv.y * s.render.height);
    fmt::print(
        "{{\"point\": [{:.17g}, {:.17g}, {:.17g}], \"width\": {}, \"height\": {}, "
        "\"pixels\": [{}]}}\n",
        p.x, p.y, p.z, s.render.width, s.render.height, list);
    return kOk;
  }
  // One line per image position, labelled: "px X py Y" (columns 2 and 4).
  for (const Vec2& uv : seen)
    fmt::print("px {:.6f} py {:.6f}\n", uv.x * s.render.width, uv.y * s.render.height);
  if (seen.empty()) fmt::print(stderr, "the camera does not see the point\n");
  return kOk;
}

}  // namespace

void add_rays(CLI::App& app, std::function<int()>& runner) {
  auto a = std::make_shared<RaysArgs>();
  CLI::App* cmd =
      app.add_subcommand("rays", "Write the camera's rays at pixel centers (.csv or .exr)");
  a->scene.add_to(*cmd);
  cmd->add_option("-o,--output", a->output,
                  "Output file: .csv (header px,py,u,v,ox,oy,oz,dx,dy,dz,valid) or .exr")
      ->required();
  cmd->callback([a, &runner] { runner = [a] { return run_rays(*a); }; });
}

void add_project(CLI::App& app, std::function<int()>& runner) {
  auto a = std::make_shared<ProjectArgs>();
  CLI::App* cmd = app.add_subcommand(
      "project",
      "Print every image position where a point appears, one line each: px X py Y "
      "(floating-point pixels from the top-left corner)");
  a->scene.add_to(*cmd);
  cmd->add_option("--point", a->point, "World point X,Y,Z")->required();
  cmd->add_option("--frame", a->frame, "The frame of the scene's [[animate]] keys (default 0)");
  cmd->add_flag("--json", a->json,
                "Print {\"point\", \"width\", \"height\", \"pixels\": [[px, py], ...]} instead");
  cmd->callback([a, &runner] { runner = [a] { return run_project(*a); }; });
}

}  // namespace anamorph::app
