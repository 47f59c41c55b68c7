// The HTTP client of http_client.h, on Boost.Beast.
#include "server/http_client.h"

#include <poll.h>

#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>

#include <cctype>
#include <cerrno>
#include <stdexcept>

namespace anamorph::test {
namespace {

namespace beast = boost::beast;
namespace http = boost::beast::http;
using tcp = boost::asio::ip::tcp;

// The socket, with reads and writes that wait at most timeout_ms (Asio's own synchronous calls
// would wait for ever).
class Stream {
 public:
  Stream(tcp::socket& s, int timeout_ms) : s_(s), timeout_ms_(timeout_ms) {}
  template <class Buffers>
  size_t read_some(const Buffers& b, beast::error_code& ec) {
    return ready(POLLIN, ec) ? s_.read_some(b, ec) : 0;
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
    return ready(POLLOUT, ec) ? s_.write_some(b, ec) : 0;
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
    if (r == 0) ec = boost::asio::error::timed_out;
    if (r < 0) ec = beast::error_code(errno, boost::system::system_category());
    return r > 0;
  }
  tcp::socket& s_;
  int timeout_ms_;
};

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

struct Connection::Impl {
  int port;
  int timeout_ms;
  boost::asio::io_context ioc;
  tcp::socket socket{ioc};
  beast::flat_buffer buffer;
};

Connection::Connection(int port, int timeout_ms) : impl_(std::make_unique<Impl>()) {
  impl_->port = port;
  impl_->timeout_ms = timeout_ms;
  impl_->socket.connect(
      {boost::asio::ip::make_address("127.0.0.1"), static_cast<unsigned short>(port)});
}

Connection::~Connection() { close(); }

int Connection::port() const { return impl_->port; }

void Connection::send_raw(const std::string& bytes) {
  Stream s(impl_->socket, impl_->timeout_ms);
  beast::net::write(s, beast::net::buffer(bytes));
}

void Connection::send(const Request& r) {
  http::request<http::string_body> req;
  req.method_string(r.method);
  req.target(r.target);
  req.version(11);
  bool has_host = false;
  for (const auto& [k, v] : r.headers) {
    req.insert(k, v);
    has_host = has_host || lower(k) == "host";
  }
  if (!has_host) req.set(http::field::host, "127.0.0.1:" + std::to_string(impl_->port));
  req.keep_alive(r.keep_alive);
  req.body() = r.body;
  if (!r.body.empty() || r.method == "POST") req.prepare_payload();
  Stream s(impl_->socket, impl_->timeout_ms);
  http::write(s, req);
}

Reply Connection::receive() {
  http::response_parser<http::string_body> parser;
  parser.body_limit(256u << 20);
  beast::error_code ec;
  Stream s(impl_->socket, impl_->timeout_ms);
  http::read(s, impl_->buffer, parser, ec);
  Reply r;
  if (ec == http::error::end_of_stream || ec == boost::asio::error::eof ||
      ec == boost::asio::error::connection_reset)
    return r;
  if (ec) throw std::runtime_error("reading the response: " + ec.message());
  const auto& res = parser.get();
  r.status = res.result_int();
  for (const auto& f : res) r.headers[lower(std::string(f.name_string()))] = std::string(f.value());
  r.body = res.body();
  return r;
}

std::string Connection::read_raw(size_t max) {
  std::string out(max, '\0');
  Stream s(impl_->socket, impl_->timeout_ms);
  out.resize(s.read_some(boost::asio::buffer(out.data(), out.size())));
  return out;
}

void Connection::close() {
  beast::error_code ec;
  impl_->socket.shutdown(tcp::socket::shutdown_both, ec);
  impl_->socket.close(ec);
}

}  // namespace anamorph::test
