// A small HTTP/1.1 server for the editor (Boost.Beast, synchronous, one thread per connection):
// few clients (a browser's tabs on this machine), so threads are simpler than an event loop and
// let a handler block, as the preview's long poll does. It limits what a client can cost: bodies
// and headers by size, connections by count, idle connections and slow requests by time.
#pragma once

#include <atomic>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace anamorph::server {

struct HttpRequest {
  std::string method;  // "GET", "POST", ...
  std::string path;    // percent-decoded, without the query
  std::map<std::string, std::string> query;
  std::map<std::string, std::string> headers;  // names in lower case
  std::string body;
  std::string header(const std::string& name) const {
    auto it = headers.find(name);
    return it == headers.end() ? std::string() : it->second;
  }
};

struct HttpResponse {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
  // Bytes held elsewhere (a preview frame), sent instead of `body` without a copy: a connection
  // thread then never allocates a frame's megabytes, which glibc would keep in that thread's
  // arena after it is freed (the load test saw RSS grow by half).
  std::shared_ptr<const std::string> shared_body;
  // A file sent from disk a piece at a time instead of `body` (a render's result: a 16K EXR is
  // gigabytes). Opened when the response is written; if it cannot be opened, the client gets 404.
  std::filesystem::path file;
  std::vector<std::pair<std::string, std::string>> headers;
};

// `client_gone()` tells a handler that blocks (a long poll) whether its client has hung up.
using HttpHandler =
    std::function<HttpResponse(const HttpRequest&, const std::function<bool()>& client_gone)>;

struct HttpOptions {
  std::string host = "127.0.0.1";
  int port = 0;                      // 0: any free port
  size_t max_body = 1 << 20;         // larger bodies get 413
  int max_connections = 32;          // more get 503
  int idle_timeout_seconds = 60;     // a connection silent this long is closed
  int request_timeout_seconds = 10;  // a request's headers and body must arrive within this (408)
};

class HttpServer {
 public:
  // Binds and listens (throws std::runtime_error naming the address when it cannot); serving
  // starts on a thread of its own.
  HttpServer(const HttpOptions& opt, HttpHandler handler);
  ~HttpServer();  // stop()
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;
  int port() const;
  // Closes the listener and every connection, and joins their threads.
  void stop();
  int connections() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// "%41b+c" -> "Ab c" (form encoding), or nullopt-like empty with ok=false on a bad escape.
bool percent_decode(const std::string& in, std::string* out, bool plus_is_space);

}  // namespace anamorph::server
