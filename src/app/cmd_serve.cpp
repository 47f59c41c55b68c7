// `anamorph serve SCENE`: the interactive camera editor, a local web server with a live preview
// (src/server, web/). It prints the page's address with its access token and runs until SIGINT,
// SIGTERM, SIGQUIT or SIGHUP (exit 0: that is how it ends).
#include <fmt/format.h>
#include <signal.h>
#include <CLI/CLI.hpp>

#ifdef __GLIBC__
#include <malloc.h>
#endif

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <thread>

#include "app/common.h"
#include "app/frame_job.h"
#include "render/renderer.h"
#include "scene/scene_loader.h"
#include "server/api.h"

namespace anamorph::app {

namespace {

namespace fs = std::filesystem;

struct ServeArgs {
  std::string scene;
  int port = 0;
  std::string host = "127.0.0.1";
  bool allow_remote = false;
  bool open = false;
  std::string token;
  std::string web;
  int threads = 0;
};

bool is_loopback(const std::string& host) {
  return host == "127.0.0.1" || host == "::1" || host == "localhost";
}

// The final render: what `anamorph render` does with the document's text, into the editor's
// private folder.
void final_render(const server::FinalRenderJob& j, int threads) {
  Scene scene = load_scene_from_string(j.text, j.scene_file, {}, j.frame);
  const Renderer renderer(scene);
  FrameJob job{scene,
               renderer,
               {},
               j.files,
               frame_metadata(scene, j.frame),
               {},
               60,
               threads,
               [&](const Progress& p) { j.progress(p.fraction, p.seconds); }};
  job.cancel = j.cancel;  // (the page's Cancel, or the server stopping)
  const FrameResult r = render_to_files(job);
  if (r.interrupted) throw std::runtime_error("cancelled");
}

// A long-running server whose requests each run on a new thread: glibc would give up to eight
// heaps per core to those threads, and memory freed in one heap is not reused by another, so a
// busy hour leaves each holding its own high-water mark (the load test saw RSS grow by a quarter
// in a minute). One heap: as many as cores still drifted once the machine was busy (+23 % in the
// load test with one core taken, against +4 % with one heap), and the server's threads allocate
// little (a tile's buffer at a time), so the lock costs nothing measurable (tests/load,
// docs/robustness.md).
void limit_heaps() {
#ifdef __GLIBC__
  mallopt(M_ARENA_MAX, 1);
#endif
}

void open_browser(const std::string& url) {
  const char* browser = std::getenv("BROWSER");
  const std::string cmd =
      fmt::format("{} '{}' >/dev/null 2>&1 &", browser && *browser ? browser : "xdg-open", url);
  if (std::system(cmd.c_str()) != 0)
    fmt::print(stderr, "could not start a browser; open the address above\n");
}

int run(const ServeArgs& a) {
  std::string host = a.host == "localhost" ? "127.0.0.1" : a.host;
  if (!is_loopback(host) && !a.allow_remote) {
    print_error(fmt::format(
        "--host {} would let other machines reach the editor; add --allow-remote if that is "
        "what you want",
        host));
    return kBadInput;
  }
  limit_heaps();
  // SIGINT, SIGTERM, SIGQUIT and SIGHUP are waited for below: blocked here, before any thread
  // starts, so that every thread (server, preview, renderer) inherits the mask and none is
  // interrupted.
  sigset_t stop_signals;
  stop_signal_set(&stop_signals);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

  const int threads = a.threads;
  server::Editor editor(a.scene,
                        [threads](const server::FinalRenderJob& j) { final_render(j, threads); });
  server::ApiOptions api_opt{a.token.empty() ? server::new_token() : a.token, host, 0, a.web};
  server::Api api(editor, api_opt);
  server::HttpOptions http_opt;
  http_opt.host = host;
  http_opt.port = a.port;
  server::HttpServer http(http_opt,
                          [&api](const server::HttpRequest& q, const std::function<bool()>& gone) {
                            return api.handle(q, gone);
                          });
  api.set_port(http.port());
  if (!is_loopback(host))
    print_warning(fmt::format(
        "listening on {}: anyone who can reach this machine and learns the token can edit {} and "
        "read the files in its folder",
        host, a.scene));
  const std::string shown = host.find(':') != std::string::npos ? "[" + host + "]" : host;
  const std::string url = fmt::format("http://{}:{}/?token={}", shown, http.port(), api_opt.token);
  fmt::print("anamorph serve: editing {}\n  open {}\n  (Ctrl-C stops the server)\n", a.scene, url);
  std::fflush(stdout);
  if (a.open) open_browser(url);
  int sig = 0;
  sigwait(&stop_signals, &sig);
  fmt::print(stderr, "stopping the editor (unsaved edits are lost)\n");
  http.stop();
  return kOk;
}

}  // namespace

void add_serve(CLI::App& app, std::function<int()>& runner) {
  auto a = std::make_shared<ServeArgs>();
  CLI::App* cmd = app.add_subcommand(
      "serve", "The interactive camera editor: a live preview in the browser (prints its address)");
  cmd->add_option("scene", a->scene, "Scene file (TOML)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--port", a->port, "Port to listen on; 0 = any free port")
      ->check(CLI::Range(0, 65535));
  cmd->add_option("--host", a->host,
                  "Address to listen on (default 127.0.0.1; another needs --allow-remote)");
  cmd->add_flag("--allow-remote", a->allow_remote,
                "Allow a --host that other machines can reach (the token still guards it)");
  cmd->add_flag("--open", a->open, "Open the page in the browser ($BROWSER or xdg-open)");
  cmd->add_option("--token", a->token, "Access token (default: a new random one)");
  cmd->add_option("--web", a->web, "Serve the page from this folder (developing web/)")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--threads", a->threads, "Threads of the final render (0 = all cores)");
  cmd->callback([a, &runner] { runner = [a] { return run(*a); }; });
}

}  // namespace anamorph::app
