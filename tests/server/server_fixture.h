// The editor's server in the test's own process: a scene in a temporary folder, an Editor on it,
// the API with a known token, and the HTTP server on 127.0.0.1 at a free port, talked to over
// loopback with the client of http_client.h.
#pragma once

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <string>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "http_client.h"
#include "io/image_io.h"
#include "render/film.h"
#include "render/renderer.h"
#include "scene/scene_loader.h"
#include "server/api.h"
#include "server/editor.h"
#include "server/http_server.h"
#include "test_util.h"

namespace anamorph::test {

namespace fs = std::filesystem;
using nlohmann::json;

// A red sphere of radius 1 at the origin, straight ahead of a perspective camera at z = 5, on a
// floor, under a point light: 64 x 48 pixels, 1 sample, Whitted (a render takes milliseconds).
inline const std::string kScene = R"([image]
width = 64
height = 48

[render]
integrator = "whitted"
spp = 1
max_depth = 4

[camera]
preset = "perspective"
look_from = [0.0, 0.0, 5.0]
look_at = [0.0, 0.0, 0.0]
fov = 50

[[material]]
name = "red"
color = [0.8, 0.2, 0.1]

[[object]]
type = "sphere"
center = [0.0, 0.0, 0.0]
radius = 1.0
material = "red"

[[object]]
type = "plane"
point = [0.0, -1.0, 0.0]

[[light]]
type = "point"
position = [4.0, 6.0, 5.0]
intensity = [90, 86, 80]
)";

// A folder of its own under the system's temporary folder, removed with its contents.
class TempFolder {
 public:
  TempFolder() {
    std::random_device rd;
    path_ = fs::temp_directory_path() /
            ("anamorph-server-test-" + std::to_string(::getpid()) + "-" + std::to_string(rd()));
    fs::create_directories(path_);
    path_ = fs::canonical(path_);
  }
  ~TempFolder() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;
  const fs::path& path() const { return path_; }
  fs::path write(const fs::path& name, const std::string& text) const {
    const fs::path p = path_ / name;
    fs::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }

 private:
  fs::path path_;
};

// Every pixel of a scene rendered into a film, as 8-bit RGBA.
inline std::vector<unsigned char> render_rgba8(const Scene& scene) {
  const Renderer renderer(scene);
  Film film(scene.render.width, scene.render.height, {});
  RenderOptions opt;
  renderer.render(film, opt);
  return film.output_rgba8();
}

// Stands in for `anamorph render` (app/cmd_serve.cpp): loads the job's text and writes its files.
inline void test_final_render(const server::FinalRenderJob& j) {
  const Scene scene = load_scene_from_string(j.text, j.scene_file, {}, j.frame);
  const Renderer renderer(scene);
  Film film(scene.render.width, scene.render.height, {});
  RenderOptions opt;
  opt.on_progress = [&](const Progress& p) { j.progress(p.fraction, p.seconds); };
  renderer.render(film, opt);
  for (const fs::path& f : j.files) write_image(f, film.output());
}

// Whether `done()` becomes true within `seconds` (checked every 20 ms).
template <class F>
bool eventually(F done, double seconds = 30) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (!done()) {
    if (std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return true;
}

class ServerTest : public ::testing::Test {
 protected:
  static constexpr const char* kToken = "0123456789abcdef0123456789abcdef";

  void SetUp() override { start(dir.write("scene.toml", kScene)); }
  void TearDown() override { stop(); }

  // The editor, API and HTTP server on `scene` (those of an earlier start() stop first).
  void start(const fs::path& scene) {
    stop();
    editor = std::make_unique<server::Editor>(scene, test_final_render);
    api = std::make_unique<server::Api>(*editor, server::ApiOptions{kToken, "127.0.0.1", 0, ""});
    http = std::make_unique<server::HttpServer>(
        server::HttpOptions{},
        [this](const server::HttpRequest& q, const std::function<bool()>& gone) {
          return api->handle(q, gone);
        });
    api->set_port(http->port());
  }
  void stop() {
    http.reset();  // first: its threads call the API
    api.reset();
    editor.reset();
  }

  int port() const { return http->port(); }
  std::string host() const { return "127.0.0.1:" + std::to_string(port()); }

  // Requests carrying the token in the header (as a script would), and `more` headers.
  Reply get(const std::string& target, Headers more = {}) {
    more.emplace_back("X-Anamorph-Token", kToken);
    return fetch(port(), {"GET", target, "", more});
  }
  Reply post(const std::string& target, const std::string& body, Headers more = {}) {
    more.emplace_back("X-Anamorph-Token", kToken);
    return fetch(port(), {"POST", target, body, more});
  }
  Reply post(const std::string& target, const json& body) { return post(target, body.dump()); }

  // The body of a JSON response (null when it is not JSON, which fails the caller's checks).
  static json body_of(const Reply& r) { return json::parse(r.body, nullptr, false); }

  json state() {
    const Reply r = get("/api/state");
    EXPECT_EQ(r.status, 200) << r.body;
    return body_of(r);
  }
  int64_t version() { return state()["version"].get<int64_t>(); }

  // POST /api/edit of one key.
  Reply edit(const std::string& key, const json& value, int64_t version) {
    const json one = {{"key", key}, {"value", value}};
    return post("/api/edit", json{{"version", version}, {"edits", json::array({one})}});
  }

  TempFolder dir;
  std::unique_ptr<server::Editor> editor;
  std::unique_ptr<server::Api> api;
  std::unique_ptr<server::HttpServer> http;
};

}  // namespace anamorph::test
