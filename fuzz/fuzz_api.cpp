// The editor's API (server/api.h) behind its HTTP layer: the first byte picks the method, the
// second an endpoint, the rest of the first line is the query, the remainder the body. Every
// request must end in an answer (a 4xx for bad input) with the server's state intact: no crash,
// no exception out of the handler, no sanitizer report. The editor edits a small scene in a
// folder of its own; its preview thread renders every state the fuzzer makes.
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "server/api.h"

using namespace anamorph;

namespace {

const char* kScene = R"(# a small scene
[image]
width = 16
height = 12
[render]
spp = 1
[camera]
preset = "perspective"
look_from = [0, 0, 4]
fov = 50
[[camera.coin]]
position = [0, 0, 1]
strength = 0.4
[[object]]
type = "sphere"
[[object]]
type = "plane"
transform = { translate = [0, -1, 0] }
[[light]]
type = "point"
position = [3, 3, 3]
intensity = [10, 10, 10]
)";

const char* kPaths[] = {"/api/declarations",
                        "/api/state",
                        "/api/edit",
                        "/api/undo",
                        "/api/redo",
                        "/api/time",
                        "/api/frame",
                        "/api/preview",
                        "/api/pick",
                        "/api/project",
                        "/api/coins",
                        "/api/magnification",
                        "/api/rays",
                        "/api/save",
                        "/api/render",
                        "/",
                        "/app.js",
                        "/nope",
                        "/api/render/result.png"};

struct Fixture {
  std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("anamorph_fuzz_api_" + std::to_string(getpid()));
  std::unique_ptr<server::Editor> editor;
  std::unique_ptr<server::Api> api;
  Fixture() {
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "scene.toml") << kScene;
    editor =
        std::make_unique<server::Editor>(dir / "scene.toml", [](const server::FinalRenderJob&) {});
    api = std::make_unique<server::Api>(*editor, server::ApiOptions{"t", "127.0.0.1", 1, ""});
  }
  ~Fixture() {
    api.reset();
    editor.reset();
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static Fixture f;
  if (size < 2 || size > (1 << 16)) return 0;
  const std::string rest(reinterpret_cast<const char*>(data + 2), size - 2);
  server::HttpRequest q;
  q.method = data[0] % 3 == 0 ? "GET" : data[0] % 3 == 1 ? "POST" : "PUT";
  q.path = kPaths[data[1] % (sizeof kPaths / sizeof *kPaths)];
  const size_t nl = rest.find('\n');
  const std::string query = rest.substr(0, nl);
  if (nl != std::string::npos) q.body = rest.substr(nl + 1);
  for (size_t s = 0, e; s < query.size(); s = e + 1) {
    e = query.find('&', s);
    if (e == std::string::npos) e = query.size();
    const std::string kv = query.substr(s, e - s);
    const size_t eq = kv.find('=');
    q.query[kv.substr(0, eq)] = eq == std::string::npos ? "" : kv.substr(eq + 1);
  }
  q.query["timeout"] = "0";  // (a long poll answers at once)
  q.headers = {{"host", "127.0.0.1:1"}, {"x-anamorph-token", "t"}};
  const server::HttpResponse r = f.api->handle(q, [] { return true; });
  if (r.status >= 500 && r.status != 503) std::abort();  // 503: the preview is not ready yet
  return 0;
}
