// A small synchronous HTTP client for the server's tests: requests with any headers (Host, Origin,
// X-Anamorph-Token, Cookie) or none, raw bytes that are not HTTP at all, and a connection that
// can be dropped mid-request. Every read and write gives up after a time, so a server that hangs
// fails the test instead of stalling the suite. Boost.Beast stays in http_client.cpp, compiled
// once: each test file that included it used to spend about 7 s instantiating it.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace anamorph::test {

struct Reply {
  int status = 0;  // 0: the server closed the connection without an answer
  std::map<std::string, std::string> headers;  // names in lower case
  std::string body;
  std::string header(const std::string& name) const {
    auto it = headers.find(name);
    return it == headers.end() ? std::string() : it->second;
  }
};

using Headers = std::vector<std::pair<std::string, std::string>>;

struct Request {
  Request(std::string method, std::string target, std::string body = {}, Headers headers = {},
          bool keep_alive = false)
      : method(std::move(method)),
        target(std::move(target)),
        body(std::move(body)),
        headers(std::move(headers)),
        keep_alive(keep_alive) {}
  std::string method, target, body;
  Headers headers;  // sent as given; Host: 127.0.0.1:PORT is added when they name no Host
  bool keep_alive;
};

// One connection to 127.0.0.1:port.
class Connection {
 public:
  explicit Connection(int port, int timeout_ms = 60000);
  ~Connection();
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;
  int port() const;

  // Bytes as they are (HTTP or not).
  void send_raw(const std::string& bytes);
  void send(const Request& r);
  // The next response; status 0 when the server closed the connection first. Throws when none
  // came within the time limit.
  Reply receive();
  // Up to `max` bytes as they come (the start of a response read by a client that then stops).
  std::string read_raw(size_t max);
  void close();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// One request on a connection of its own, and its response.
inline Reply fetch(int port, const Request& r) {
  Connection c(port);
  c.send(r);
  return c.receive();
}

// Raw bytes on a connection of its own, and the response if one came before the server closed.
inline Reply fetch_raw(int port, const std::string& bytes, int timeout_ms = 60000) {
  Connection c(port, timeout_ms);
  c.send_raw(bytes);
  return c.receive();
}

}  // namespace anamorph::test
