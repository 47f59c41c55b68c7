// The editor's HTTP API and page: routes requests to the Editor, and guards them. Every request
// must carry the server's token (header X-Anamorph-Token, the cookie the page gets, or ?token=),
// a Host header naming the server's own address (no DNS rebinding), and an Origin, when the
// browser sends one, of the server itself (no cross-site requests). Bodies are JSON; a malformed
// one or a bad value gets 400 with a message, and the server goes on.
#pragma once

#include <string>

#include "server/editor.h"
#include "server/http_server.h"

namespace anamorph::server {

struct ApiOptions {
  std::string token;
  std::string host;  // the address the server listens on
  int port = 0;
  std::string web_folder;  // "" = the page built into the binary; else served from this folder
};

class Api {
 public:
  Api(Editor& editor, ApiOptions opt) : editor_(editor), opt_(std::move(opt)) {}
  HttpResponse handle(const HttpRequest& q, const std::function<bool()>& client_gone);
  void set_port(int port) { opt_.port = port; }

 private:
  std::optional<HttpResponse> refuse(const HttpRequest& q) const;
  // An /api/ call through the route table (server/api_routes.cpp).
  HttpResponse route_api(const HttpRequest& q, const std::function<bool()>& client_gone);
  HttpResponse page(const HttpRequest& q) const;
  Editor& editor_;
  ApiOptions opt_;
};

// A new random token (32 hex digits from the system's random source).
std::string new_token();

}  // namespace anamorph::server
