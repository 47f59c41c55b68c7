// The HTTP server alone, with handlers of the test's own: what it costs a client at most (idle
// time, connections), handlers that throw or block, and URL decoding.
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <list>
#include <thread>

#include "http_client.h"
#include "server/http_server.h"
#include "server_fixture.h"

namespace anamorph::test {
namespace {

using server::HttpOptions;
using server::HttpRequest;
using server::HttpResponse;
using server::HttpServer;

// Answers with the request's method, path and query.
HttpResponse echo(const HttpRequest& q, const std::function<bool()>&) {
  HttpResponse r;
  r.content_type = "text/plain";
  r.body = q.method + " " + q.path;
  for (const auto& [k, v] : q.query) r.body += " " + k + "=" + v;
  return r;
}

TEST(HttpServer, DecodesPathAndQuery) {
  HttpServer http({}, echo);
  const Reply r = fetch(http.port(), {"GET", "/a%20b/c?x=1+2&y=%26&z"});
  EXPECT_EQ(r.status, 200);
  EXPECT_EQ(r.body, "GET /a b/c x=1 2 y=& z=");
}

TEST(HttpServer, PercentDecode) {
  std::string out;
  EXPECT_TRUE(server::percent_decode("%41b+c%2f", &out, true));
  EXPECT_EQ(out, "Ab c/");
  EXPECT_TRUE(server::percent_decode("a+b", &out, false));
  EXPECT_EQ(out, "a+b");
  for (const std::string bad : {"%", "%4", "%zz", "a%4g", "%%41"})
    EXPECT_FALSE(server::percent_decode(bad, &out, false)) << bad << " -> " << out;
}

TEST(HttpServer, HandlerThatThrowsIs500AndTheServerGoesOn) {
  HttpServer http({}, [](const HttpRequest& q, const std::function<bool()>& gone) {
    if (q.path == "/throw") throw std::runtime_error("boom");
    return echo(q, gone);
  });
  const Reply r = fetch(http.port(), {"GET", "/throw"});
  EXPECT_EQ(r.status, 500);
  EXPECT_NE(r.body.find("boom"), std::string::npos) << r.body;
  EXPECT_EQ(fetch(http.port(), {"GET", "/ok"}).status, 200);
}

TEST(HttpServer, IdleConnectionIsClosed) {
  HttpOptions opt;
  opt.idle_timeout_seconds = 1;
  HttpServer http(opt, echo);
  Connection c(http.port());
  ASSERT_TRUE(eventually([&] { return http.connections() == 1; }, 10)) << http.connections();
  EXPECT_TRUE(eventually([&] { return http.connections() == 0; }, 10))
      << http.connections() << " connections after 10 s of silence";
  EXPECT_EQ(c.receive().status, 0);  // (closed without an answer)
}

TEST(HttpServer, ConnectionsOverTheLimitAre503) {
  HttpOptions opt;
  opt.max_connections = 3;
  HttpServer http(opt, echo);
  {
    std::list<Connection> held;
    for (int i = 0; i < opt.max_connections; ++i) held.emplace_back(http.port());
    ASSERT_TRUE(eventually([&] { return http.connections() == opt.max_connections; }, 10))
        << http.connections();
    const Reply r = fetch(http.port(), {"GET", "/"});
    EXPECT_EQ(r.status, 503) << r.body;
  }
  ASSERT_TRUE(eventually([&] { return http.connections() == 0; }, 10)) << http.connections();
  EXPECT_EQ(fetch(http.port(), {"GET", "/"}).status, 200);
}

TEST(HttpServer, ARequestTrickledInIsAnswered408WhileOthersAreServed) {
  HttpOptions opt;
  opt.request_timeout_seconds = 1;  // (the idle time stays 60 s)
  HttpServer http(opt, echo);
  Connection slow(http.port(), 10000);
  // A byte every 200 ms for 0.8 s: never silent for long, so only the request's own deadline can
  // end it; other clients are served meanwhile.
  for (const char c : std::string("GET ")) {
    slow.send_raw(std::string(1, c));
    EXPECT_EQ(fetch(http.port(), {"GET", "/other"}).status, 200) << "a slow client blocked others";
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  const auto t0 = std::chrono::steady_clock::now();
  const Reply r = slow.receive();
  const double waited =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(r.status, 408) << r.body << " (after " << waited << " s more)";
  EXPECT_NE(r.body.find("within 1 s"), std::string::npos) << r.body;
  EXPECT_TRUE(eventually([&] { return http.connections() == 0; }, 10)) << http.connections();
}

TEST(HttpServer, AFloodOfConnectionsStartsABoundedNumberOfThreads) {
  HttpOptions opt;
  opt.max_connections = 2;
  HttpServer http(opt, echo);
  std::list<Connection> flood;
  for (int i = 0; i < 60; ++i) flood.emplace_back(http.port());
  // (Each accepted connection has a thread until it ends; the flood's are closed at once past
  // the limit and the refusals' margin.)
  ASSERT_TRUE(eventually([&] { return http.connections() >= opt.max_connections; }, 10));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_LE(http.connections(), opt.max_connections + 16);
  flood.clear();
  ASSERT_TRUE(eventually([&] { return http.connections() == 0; }, 10)) << http.connections();
  EXPECT_EQ(fetch(http.port(), {"GET", "/"}).status, 200);
}

// Resident set of this process in bytes.
size_t resident_bytes() {
  std::ifstream statm("/proc/self/statm");
  size_t pages = 0, resident = 0;
  statm >> pages >> resident;
  return resident * size_t(sysconf(_SC_PAGESIZE));
}

// A render's result is sent from its file a piece at a time: a client that reads the first bytes
// of a 64 MiB file and stops holds a connection, not the file in the server's memory.
TEST(HttpServer, AFileIsSentFromDiskInPieces) {
  const auto dir = std::filesystem::path(::testing::TempDir()) / "http_file_body";
  std::filesystem::create_directories(dir);
  const auto file = dir / "big.bin";
  std::string bytes(64u << 20, '\0');
  for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = char((i * 2654435761u) >> 13);
  std::ofstream(file, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
  HttpServer http({}, [&](const HttpRequest& q, const std::function<bool()>& gone) {
    HttpResponse r;
    r.content_type = "application/octet-stream";
    if (q.path == "/file") r.file = file;
    if (q.path == "/missing") r.file = dir / "missing.bin";
    return r.file.empty() ? echo(q, gone) : r;
  });

  const Reply whole = fetch(http.port(), {"GET", "/file"});
  ASSERT_EQ(whole.status, 200);
  EXPECT_EQ(whole.header("content-length"), std::to_string(bytes.size()));
  EXPECT_EQ(whole.header("content-type"), "application/octet-stream");
  ASSERT_EQ(whole.body.size(), bytes.size());
  EXPECT_TRUE(whole.body == bytes) << "the bytes sent differ from the file's";
  EXPECT_EQ(fetch(http.port(), {"GET", "/missing"}).status, 404);

  const size_t before = resident_bytes();
  {
    Connection slow(http.port());
    slow.send({"GET", "/file"});
    const std::string start = slow.read_raw(4096);
    EXPECT_EQ(start.substr(0, 15), "HTTP/1.1 200 OK") << start.substr(0, 100);
    // The server is now blocked writing to a client that does not read; others are served.
    EXPECT_EQ(fetch(http.port(), {"GET", "/ok"}).body, "GET /ok");
    const size_t during = resident_bytes();
    EXPECT_LT(during, before + (16u << 20))
        << "RSS grew by " << (during - before) / 1024 << " KiB while a 64 MiB file was sent";
  }
  EXPECT_TRUE(eventually([&] { return http.connections() == 0; }, 10)) << http.connections();
  std::filesystem::remove_all(dir);
}

TEST(HttpServer, StopEndsABlockedHandler) {
  std::atomic<bool> waiting{false};
  auto http = std::make_unique<HttpServer>(
      HttpOptions{}, [&](const HttpRequest&, const std::function<bool()>& gone) {
        waiting = true;
        const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(30);
        while (!gone() && std::chrono::steady_clock::now() < end)
          std::this_thread::sleep_for(std::chrono::milliseconds(10));
        return HttpResponse{};
      });
  Connection c(http->port());
  c.send({"GET", "/", "", {}, true});
  ASSERT_TRUE(eventually([&] { return waiting.load(); }, 10));
  const auto t0 = std::chrono::steady_clock::now();
  http.reset();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(seconds, 10) << "stop() waited for the handler";
}

TEST(HttpServer, RefusesAnAddressItCannotUse) {
  HttpOptions opt;
  const auto listen = [&] { HttpServer s(opt, echo); };
  opt.host = "not-an-address";
  EXPECT_THROW(listen(), std::runtime_error);
  HttpServer first({}, echo);
  opt.host = "127.0.0.1";
  opt.port = first.port();
  EXPECT_THROW(listen(), std::runtime_error);
}

}  // namespace
}  // namespace anamorph::test
