// A small synchronous HTTP client (Boost.Beast) for the server's tests: requests with any headers
// (Host, Origin, X-Anamorph-Token, Cookie) or none, raw bytes that are not HTTP at all, and a
// connection that can be dropped mid-request. Every read and write gives up after a time, so a
// server that hangs fails the test instead of stalling the suite.
#pragma once

#include <poll.h>

#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>

#include <cctype>
#include <map>
#include <stdexcept>
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
  explicit Connection(int port, int timeout_ms = 60000) : port_(port), timeout_ms_(timeout_ms) {
    namespace net = boost::asio;
    socket_.connect({net::ip::make_address("127.0.0.1"), static_cast<unsigned short>(port)});
  }
  ~Connection() { close(); }
  int port() const { return port_; }

  // Bytes as they are (HTTP or not).
  void send_raw(const std::string& bytes) {
    Stream s(socket_, timeout_ms_);
    boost::beast::net::write(s, boost::beast::net::buffer(bytes));
  }

  void send(const Request& r) {
    namespace http = boost::beast::http;
    http::request<http::string_body> req;
    req.method_string(r.method);
    req.target(r.target);
    req.version(11);
    bool has_host = false;
    for (const auto& [k, v] : r.headers) {
      req.insert(k, v);
      has_host = has_host || lower(k) == "host";
    }
    if (!has_host) req.set(http::field::host, "127.0.0.1:" + std::to_string(port_));
    req.keep_alive(r.keep_alive);
    req.body() = r.body;
    if (!r.body.empty() || r.method == "POST") req.prepare_payload();
    Stream s(socket_, timeout_ms_);
    http::write(s, req);
  }

  // The next response; status 0 when the server closed the connection first. Throws when none
  // came within the time limit.
  Reply receive() {
    namespace http = boost::beast::http;
    http::response_parser<http::string_body> parser;
    parser.body_limit(256u << 20);
    boost::beast::error_code ec;
    Stream s(socket_, timeout_ms_);
    http::read(s, buffer_, parser, ec);
    Reply r;
    if (ec == http::error::end_of_stream || ec == boost::asio::error::eof ||
        ec == boost::asio::error::connection_reset)
      return r;
    if (ec) throw std::runtime_error("reading the response: " + ec.message());
    const auto& res = parser.get();
    r.status = res.result_int();
    for (const auto& f : res)
      r.headers[lower(std::string(f.name_string()))] = std::string(f.value());
    r.body = res.body();
    return r;
  }

  // Up to `max` bytes as they come (the start of a response read by a client that then stops).
  std::string read_raw(size_t max) {
    std::string out(max, '\0');
    Stream s(socket_, timeout_ms_);
    out.resize(s.read_some(boost::asio::buffer(out.data(), out.size())));
    return out;
  }

  void close() {
    boost::beast::error_code ec;
    socket_.shutdown(boost::asio::ip::tcp::socket::shutdown_both, ec);
    socket_.close(ec);
  }

 private:
  // The socket, with reads and writes that wait at most timeout_ms (Asio's own synchronous calls
  // would wait for ever).
  class Stream {
   public:
    Stream(boost::asio::ip::tcp::socket& s, int timeout_ms) : s_(s), timeout_ms_(timeout_ms) {}
    template <class Buffers>
    size_t read_some(const Buffers& b, boost::beast::error_code& ec) {
      return ready(POLLIN, ec) ? s_.read_some(b, ec) : 0;
    }
    template <class Buffers>
    size_t read_some(const Buffers& b) {
      boost::beast::error_code ec;
      const size_t n = read_some(b, ec);
      if (ec) throw boost::beast::system_error(ec);
      return n;
    }
    template <class Buffers>
    size_t write_some(const Buffers& b, boost::beast::error_code& ec) {
      return ready(POLLOUT, ec) ? s_.write_some(b, ec) : 0;
    }
    template <class Buffers>
    size_t write_some(const Buffers& b) {
      boost::beast::error_code ec;
      const size_t n = write_some(b, ec);
      if (ec) throw boost::beast::system_error(ec);
      return n;
    }

   private:
    bool ready(short events, boost::beast::error_code& ec) {
      pollfd p{s_.native_handle(), events, 0};
      const int r = ::poll(&p, 1, timeout_ms_);
      if (r == 0) ec = boost::asio::error::timed_out;
      if (r < 0) ec = boost::beast::error_code(errno, boost::system::system_category());
      return r > 0;
    }
    boost::asio::ip::tcp::socket& s_;
    int timeout_ms_;
  };

  static std::string lower(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
  }

  int port_;
  int timeout_ms_;
  boost::asio::io_context ioc_;
  boost::asio::ip::tcp::socket socket_{ioc_};
  boost::beast::flat_buffer buffer_;
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
