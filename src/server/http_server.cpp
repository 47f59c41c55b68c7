#include "server/http_server.h"

#include <poll.h>
#include <sys/socket.h>

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>

#include <algorithm>
#include <chrono>
#include <list>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <thread>

#include "server/http_headers.h"

namespace anamorph::server {

namespace {

namespace net = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = net::ip::tcp;

// A socket whose reads and writes give up after a time: Asio's synchronous calls wait on poll()
// themselves and ignore SO_RCVTIMEO, so the wait is ours. Beast reads and writes through it (it
// is a SyncReadStream and SyncWriteStream). Each wait lasts at most `timeout_ms`, and none goes
// past the deadline when one is set: a client that trickles a request byte by byte cannot keep
// its connection by never falling silent for long.
class TimedSocket {
 public:
  using Clock = std::chrono::steady_clock;
  TimedSocket(tcp::socket& s, int timeout_ms) : s_(s), timeout_ms_(timeout_ms) {}
  void set_deadline(Clock::time_point t) { deadline_ = t; }
  void clear_deadline() { deadline_.reset(); }
  // Waits up to the idle time for the next byte (true) or for the peer to close or fail.
  bool wait_readable(beast::error_code& ec) { return ready(POLLIN, ec); }
  template <class Buffers>
  size_t read_some(const Buffers& b, beast::error_code& ec) {
    if (!ready(POLLIN, ec)) return 0;
    return s_.read_some(b, ec);
  }
  template <class Buffers>
  size_t read_some(const Buffers& b) {
    beast::error_code ec;
    const size_t n = read_some(b, ec);
    if (ec) throw beast::system_error(ec);
    return n;
  }
  template <class Buffers>
  size_t write_some(const Buffers& b, beast::error_code& ec) {
    if (!ready(POLLOUT, ec)) return 0;
    return s_.write_some(b, ec);
  }
  template <class Buffers>
  size_t write_some(const Buffers& b) {
    beast::error_code ec;
    const size_t n = write_some(b, ec);
    if (ec) throw beast::system_error(ec);
    return n;
  }

 private:
  bool ready(short events, beast::error_code& ec) {
    int wait = timeout_ms_;
    if (deadline_) {
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(*deadline_ - Clock::now());
      wait = int(std::clamp<int64_t>(left.count(), 0, timeout_ms_));
    }
    pollfd p{s_.native_handle(), events, 0};
    const int r = ::poll(&p, 1, wait);
    if (r == 0) ec = net::error::timed_out;
    if (r < 0) ec = beast::error_code(errno, boost::system::system_category());
    return r > 0;
  }
  tcp::socket& s_;
  int timeout_ms_;
  std::optional<Clock::time_point> deadline_;
};

// Whether the peer closed its end (a read would return end of file), without consuming data.
bool peer_closed(int fd) {
  char c;
  const ssize_t n = ::recv(fd, &c, 1, MSG_PEEK | MSG_DONTWAIT);
  return n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR);
}

// `*ok` false for a malformed percent-escape; `*problem` set when the headers break a rule of
// http_headers.h or the query names a parameter twice (which one counts would be a guess).
HttpRequest to_request(const http::request<http::string_body>& r, bool* ok,
                       std::optional<std::string>* problem) {
  HttpRequest q;
  q.method = std::string(r.method_string());
  const std::string target(r.target());
  const size_t qm = target.find('?');
  *ok = percent_decode(target.substr(0, qm), &q.path, false);
  if (qm != std::string::npos) {
    const std::string qs = target.substr(qm + 1);
    for (size_t s = 0, e; s < qs.size(); s = e + 1) {
      e = qs.find('&', s);
      if (e == std::string::npos) e = qs.size();
      const std::string kv = qs.substr(s, e - s);
      const size_t eq = kv.find('=');
      std::string k, v;
      *ok = percent_decode(kv.substr(0, eq), &k, true) && *ok;
      if (eq != std::string::npos) *ok = percent_decode(kv.substr(eq + 1), &v, true) && *ok;
      if (!k.empty() && !q.query.emplace(k, v).second && !*problem)
        *problem = "?" + k + "= is given twice";
    }
  }
  std::vector<std::pair<std::string, std::string>> fields;
  for (const auto& f : r) fields.emplace_back(std::string(f.name_string()), std::string(f.value()));
  if (auto why = check_headers(fields, &q.headers)) *problem = std::move(why);
  q.body = r.body();
  return q;
}

// The response as Beast writes it, with `Body` (string_body, or span_body over shared bytes).
template <class Body>
http::response<Body> to_beast(const HttpResponse& r, unsigned version, bool keep_alive,
                              typename Body::value_type body) {
  http::response<Body> res{static_cast<http::status>(r.status), version};
  res.set(http::field::server, "anamorph");
  res.set(http::field::content_type, r.content_type);
  for (const auto& [k, v] : r.headers) res.set(k, v);
  res.body() = std::move(body);
  res.keep_alive(keep_alive);
  res.prepare_payload();
  return res;
}

HttpResponse plain(int status, std::string text) {
  HttpResponse r;
  r.status = status;
  r.content_type = "text/plain; charset=utf-8";
  r.body = std::move(text);
  return r;
}

}  // namespace

bool percent_decode(const std::string& in, std::string* out, bool plus_is_space) {
  out->clear();
  for (size_t i = 0; i < in.size(); ++i) {
    const char c = in[i];
    if (c == '+' && plus_is_space) {
      out->push_back(' ');
    } else if (c != '%') {
      out->push_back(c);
    } else {
      if (i + 2 >= in.size() || !std::isxdigit(static_cast<unsigned char>(in[i + 1])) ||
          !std::isxdigit(static_cast<unsigned char>(in[i + 2])))
        return false;
      out->push_back(char(std::stoi(in.substr(i + 1, 2), nullptr, 16)));
      i += 2;
    }
  }
  return true;
}

struct HttpServer::Impl {
  static constexpr int kRefusalThreads = 16;
  struct Connection {
    std::shared_ptr<tcp::socket> socket;
    std::thread thread;
    std::atomic<bool> done{false};
  };

  HttpOptions opt;
  HttpHandler handler;
  net::io_context ioc{1};
  tcp::acceptor acceptor{ioc};
  std::thread accept_thread;
  mutable std::mutex mu;  // connections, stopped
  std::list<Connection> connections;
  bool stopped = false;
  int port = 0;

  void accept_loop() {
    for (;;) {
      auto socket = std::make_shared<tcp::socket>(ioc);
      beast::error_code ec;
      acceptor.accept(*socket, ec);
      std::lock_guard lock(mu);
      if (stopped) return;
      if (ec) continue;  // (a connection reset before it was accepted)
      reap();
      // Past the limit a connection is answered 503 on a thread of its own; far past it (a
      // flood) it is closed at once, so that no client can make the server start threads
      // without bound.
      if (int(connections.size()) >= opt.max_connections + kRefusalThreads) {
        socket->close(ec);
        continue;
      }
      Connection& c = connections.emplace_back();
      c.socket = socket;
      const bool over = int(connections.size()) > opt.max_connections;
      c.thread = std::thread([this, &c, over] {
        serve(*c.socket, over);
        c.done = true;
      });
    }
  }

  // Joins the threads of connections that ended (under mu).
  void reap() {
    for (auto it = connections.begin(); it != connections.end();) {
      if (it->done) {
        it->thread.join();
        it = connections.erase(it);
      } else {
        ++it;
      }
    }
  }

  void serve(tcp::socket& socket, bool over_limit) {
    using Clock = TimedSocket::Clock;
    TimedSocket stream(socket, opt.idle_timeout_seconds * 1000);
    beast::flat_buffer buffer;
    const int fd = socket.native_handle();
    const std::function<bool()> gone = [fd] { return peer_closed(fd); };
    // A connection past the limit only waits briefly for the request it is refused.
    const auto request_time = std::chrono::seconds(over_limit ? 2 : opt.request_timeout_seconds);
    if (over_limit) stream.set_deadline(Clock::now() + request_time);
    for (;;) {
      beast::error_code ec;
      // Idle between requests for up to the idle time; from a request's first byte, all of it
      // (headers and body) within the request time.
      if (buffer.size() == 0 && !stream.wait_readable(ec)) break;
      if (!over_limit) stream.set_deadline(Clock::now() + request_time);
      http::request_parser<http::string_body> parser;
      parser.body_limit(opt.max_body);
      parser.header_limit(16 * 1024);
      http::read(stream, buffer, parser, ec);
      if (ec) {
        if (refuse_unread(stream, ec, parser.got_some() || buffer.size() > 0)) linger(socket);
        break;
      }
      const auto& req = parser.get();
      stream.clear_deadline();
      if (over_limit) {
        reply(stream, plain(503, "too many connections\n"), req.version(), false);
        break;
      }
      bool ok = true;
      std::optional<std::string> problem;
      const HttpRequest q = to_request(req, &ok, &problem);
      HttpResponse r;
      if (problem) {
        r = plain(400, *problem + "\n");
      } else if (!ok) {
        r = plain(400, "malformed percent-encoding in the URL\n");
      } else {
        try {
          r = handler(q, gone);
        } catch (const std::exception& e) {
          r = plain(500, std::string("internal error: ") + e.what() + "\n");
        }
      }
      if (!reply(stream, r, req.version(), req.keep_alive())) break;
      if (!req.keep_alive()) break;
    }
    beast::error_code ec;
    socket.shutdown(tcp::socket::shutdown_both, ec);
    socket.close(ec);
  }

  // Answers a request that could not be read when it deserves an answer (too large, too slow,
  // malformed: true); a connection that just ended (closed, reset, idle) gets none.
  bool refuse_unread(TimedSocket& stream, const beast::error_code& ec, bool got_some) const {
    if (ec == http::error::body_limit) {
      reply(
          stream,
          plain(413, "request body too large (limit " + std::to_string(opt.max_body) + " bytes)\n"),
          11, false);
    } else if (ec == http::error::header_limit) {
      reply(stream, plain(431, "request headers too large\n"), 11, false);
    } else if (ec == net::error::timed_out) {
      if (!got_some) return false;
      reply(stream,
            plain(408, "the request did not arrive within " +
                           std::to_string(opt.request_timeout_seconds) + " s\n"),
            11, false);
    } else if (ec == http::error::end_of_stream || ec == net::error::eof ||
               ec == net::error::connection_reset || !got_some) {
      return false;
    } else {
      reply(stream, plain(400, "malformed HTTP request\n"), 11, false);
    }
    return true;
  }

  // After refusing a request whose bytes are still arriving (a body over the limit), reads and
  // drops them for a moment before closing: closing with unread input would reset the
  // connection, and the client could lose the answer that says why (a "lingering close").
  static void linger(tcp::socket& socket) {
    beast::error_code ec;
    socket.shutdown(tcp::socket::shutdown_send, ec);
    TimedSocket stream(socket, 2000);
    stream.set_deadline(TimedSocket::Clock::now() + std::chrono::seconds(2));
    char sink[1 << 16];
    for (size_t total = 0; total < (8u << 20);) {
      const size_t n = stream.read_some(net::buffer(sink), ec);
      if (ec || n == 0) break;
      total += n;
    }
  }

  // Writes a response, all of it within the idle time (a client that reads a byte now and then
  // does not keep its thread).
  bool reply(TimedSocket& stream, const HttpResponse& r, unsigned version, bool keep_alive) const {
    beast::error_code ec;
    stream.set_deadline(TimedSocket::Clock::now() + std::chrono::seconds(opt.idle_timeout_seconds));
    if (!r.file.empty()) return reply_file(stream, r, version, keep_alive);
    if (r.shared_body) {
      const std::string& bytes = *r.shared_body;  // (kept alive by r while this writes)
      auto res = to_beast<http::span_body<const char>>(r, version, keep_alive,
                                                       {bytes.data(), bytes.size()});
      http::write(stream, res, ec);
    } else {
      auto res = to_beast<http::string_body>(r, version, keep_alive, r.body);
      http::write(stream, res, ec);
    }
    stream.clear_deadline();
    return !ec;
  }

  // A file in pieces: memory is Beast's buffer, not the file. The deadline is the idle time plus
  // a second per 64 KiB, so a slow reader of a big file is served while one that stops is not.
  bool reply_file(TimedSocket& stream, const HttpResponse& r, unsigned version,
                  bool keep_alive) const {
    beast::error_code ec;
    http::file_body::value_type body;
    body.open(r.file.c_str(), beast::file_mode::scan, ec);
    if (ec)
      return reply(stream, plain(404, "cannot read " + r.file.filename().string() + "\n"), version,
                   keep_alive);
    const auto seconds = opt.idle_timeout_seconds + int64_t(body.size() >> 16);
    auto res = to_beast<http::file_body>(r, version, keep_alive, std::move(body));
    stream.set_deadline(TimedSocket::Clock::now() + std::chrono::seconds(seconds));
    http::write(stream, res, ec);
    stream.clear_deadline();
    return !ec;
  }
};

HttpServer::HttpServer(const HttpOptions& opt, HttpHandler handler) : impl_(new Impl) {
  impl_->opt = opt;
  impl_->handler = std::move(handler);
  beast::error_code ec;
  const auto address = net::ip::make_address(opt.host, ec);
  if (ec) throw std::runtime_error("not an IP address: '" + opt.host + "'");
  const tcp::endpoint ep{address, static_cast<unsigned short>(opt.port)};
  auto& a = impl_->acceptor;
  a.open(ep.protocol(), ec);
  if (!ec) a.set_option(net::socket_base::reuse_address(true), ec);
  if (!ec) a.bind(ep, ec);
  if (!ec) a.listen(net::socket_base::max_listen_connections, ec);
  if (ec)
    throw std::runtime_error("cannot listen on " + opt.host + ":" + std::to_string(opt.port) +
                             ": " + ec.message());
  impl_->port = a.local_endpoint().port();
  impl_->accept_thread = std::thread([this] { impl_->accept_loop(); });
}

HttpServer::~HttpServer() { stop(); }

int HttpServer::port() const { return impl_->port; }

int HttpServer::connections() const {
  std::lock_guard lock(impl_->mu);
  int n = 0;
  for (const auto& c : impl_->connections) n += c.done ? 0 : 1;
  return n;
}

void HttpServer::stop() {
  {
    std::lock_guard lock(impl_->mu);
    if (impl_->stopped) return;
    impl_->stopped = true;
    // shutdown() wakes a thread blocked in accept() or poll() on these sockets; close() would not.
    ::shutdown(impl_->acceptor.native_handle(), SHUT_RDWR);
    for (auto& c : impl_->connections) ::shutdown(c.socket->native_handle(), SHUT_RDWR);
  }
  impl_->accept_thread.join();
  for (auto& c : impl_->connections) c.thread.join();
  impl_->connections.clear();
  beast::error_code ec;
  impl_->acceptor.close(ec);
}

}  // namespace anamorph::server
