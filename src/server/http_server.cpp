#include "server/http_server.h"

#include <poll.h>
#include <sys/socket.h>

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>

#include <list>
#include <mutex>
#include <stdexcept>
#include <thread>

namespace anamorph::server {

namespace {

namespace net = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = net::ip::tcp;

// A socket whose reads and writes give up after a time: Asio's synchronous calls wait on poll()
// themselves and ignore SO_RCVTIMEO, so the wait is ours. Beast reads and writes through it (it
// is a SyncReadStream and SyncWriteStream).
class TimedSocket {
 public:
  TimedSocket(tcp::socket& s, int timeout_ms) : s_(s), timeout_ms_(timeout_ms) {}
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
    pollfd p{s_.native_handle(), events, 0};
    const int r = ::poll(&p, 1, timeout_ms_);
    if (r == 0) ec = net::error::timed_out;
    if (r < 0) ec = beast::error_code(errno, boost::system::system_category());
    return r > 0;
  }
  tcp::socket& s_;
  int timeout_ms_;
};

// Whether the peer closed its end (a read would return end of file), without consuming data.
bool peer_closed(int fd) {
  char c;
  const ssize_t n = ::recv(fd, &c, 1, MSG_PEEK | MSG_DONTWAIT);
  return n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR);
}

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

HttpRequest to_request(const http::request<http::string_body>& r, bool* ok) {
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
      if (!k.empty()) q.query[k] = v;
    }
  }
  for (const auto& f : r) q.headers[lower(std::string(f.name_string()))] = std::string(f.value());
  q.body = r.body();
  return q;
}

http::response<http::string_body> to_beast(const HttpResponse& r, unsigned version,
                                           bool keep_alive) {
  http::response<http::string_body> res{static_cast<http::status>(r.status), version};
  res.set(http::field::server, "anamorph");
  res.set(http::field::content_type, r.content_type);
  for (const auto& [k, v] : r.headers) res.set(k, v);
  res.body() = r.body;
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
    TimedSocket stream(socket, opt.idle_timeout_seconds * 1000);
    beast::flat_buffer buffer;
    const int fd = socket.native_handle();
    const std::function<bool()> gone = [fd] { return peer_closed(fd); };
    for (;;) {
      http::request_parser<http::string_body> parser;
      parser.body_limit(opt.max_body);
      parser.header_limit(16 * 1024);
      beast::error_code ec;
      http::read(stream, buffer, parser, ec);
      if (ec == http::error::body_limit) {
        reply(stream,
              plain(413,
                    "request body too large (limit " + std::to_string(opt.max_body) + " bytes)\n"),
              11, false);
        break;
      }
      if (ec == http::error::header_limit) {
        reply(stream, plain(431, "request headers too large\n"), 11, false);
        break;
      }
      if (ec) {
        if (ec != http::error::end_of_stream && ec != net::error::timed_out &&
            ec != net::error::eof && ec != net::error::connection_reset && !buffer.size())
          break;
        if (ec == http::error::end_of_stream || ec == net::error::eof ||
            ec == net::error::timed_out || ec == net::error::connection_reset)
          break;
        reply(stream, plain(400, "malformed HTTP request\n"), 11, false);
        break;
      }
      const auto& req = parser.get();
      if (over_limit) {
        reply(stream, plain(503, "too many connections\n"), req.version(), false);
        break;
      }
      bool ok = true;
      const HttpRequest q = to_request(req, &ok);
      HttpResponse r;
      if (!ok) {
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

  static bool reply(TimedSocket& stream, const HttpResponse& r, unsigned version, bool keep_alive) {
    auto res = to_beast(r, version, keep_alive);
    beast::error_code ec;
    http::write(stream, res, ec);
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
