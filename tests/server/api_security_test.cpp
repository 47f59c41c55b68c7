// What the server refuses: requests without the token, with another site's Host (DNS rebinding)
// or Origin, and malformed requests (bad JSON, bad HTTP, huge bodies, bad escapes), after which
// it goes on serving.
#include "server_fixture.h"

namespace anamorph::test {
namespace {

using SecurityTest = ServerTest;
using namespace std::string_literals;

TEST_F(SecurityTest, TokenIsRequiredInHeaderCookieOrQuery) {
  EXPECT_EQ(fetch(port(), {"GET", "/api/state"}).status, 401);
  EXPECT_EQ(fetch(port(), {"GET", "/api/state", "", {{"X-Anamorph-Token", "wrong"}}}).status, 401);
  EXPECT_EQ(fetch(port(), {"GET", "/api/state", "", {{"Cookie", "anamorph_token=wrong"}}}).status,
            401);
  EXPECT_EQ(fetch(port(), {"GET", "/api/state?token=wrong"}).status, 401);
  // The right token one character short, and one character longer.
  const std::string t = kToken;
  EXPECT_EQ(fetch(port(), {"GET", "/api/state?token=" + t.substr(1)}).status, 401);
  EXPECT_EQ(fetch(port(), {"GET", "/api/state?token=" + t + "0"}).status, 401);

  const Reply header = fetch(port(), {"GET", "/api/state", "", {{"X-Anamorph-Token", t}}});
  EXPECT_EQ(header.status, 200) << header.body;
  const Reply cookie =
      fetch(port(), {"GET", "/api/state", "", {{"Cookie", "theme=dark; anamorph_token=" + t}}});
  EXPECT_EQ(cookie.status, 200) << cookie.body;
  const Reply query = fetch(port(), {"GET", "/api/state?token=" + t});
  EXPECT_EQ(query.status, 200) << query.body;
  EXPECT_EQ(body_of(query)["version"], 1) << query.body;

  const Reply refused = fetch(port(), {"GET", "/api/state"});
  EXPECT_TRUE(body_of(refused).contains("error")) << refused.body;
  EXPECT_EQ(refused.body.find("\"document\""), std::string::npos) << refused.body;
}

TEST_F(SecurityTest, PageSetsAnHttpOnlySameSiteCookie) {
  const Reply r = fetch(port(), {"GET", "/?token=" + std::string(kToken)});
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(r.header("content-type").rfind("text/html", 0), 0u) << r.header("content-type");
  const std::string cookie = r.header("set-cookie");
  EXPECT_NE(cookie.find(std::string("anamorph_token=") + kToken), std::string::npos) << cookie;
  EXPECT_NE(cookie.find("HttpOnly"), std::string::npos) << cookie;
  EXPECT_NE(cookie.find("SameSite=Strict"), std::string::npos) << cookie;
  EXPECT_EQ(fetch(port(), {"GET", "/"}).status, 401);
}

TEST_F(SecurityTest, HostMustNameTheServer) {
  const std::string p = ":" + std::to_string(port());
  for (const std::string& host :
       std::vector<std::string>{"evil.example" + p, "127.0.0.1", "127.0.0.1:1"}) {
    const Reply r = get("/api/state", {{"Host", host}});
    EXPECT_EQ(r.status, 403) << "Host '" << host << "': " << r.body;
  }
  for (const std::string& host : std::vector<std::string>{"127.0.0.1" + p, "localhost" + p}) {
    const Reply r = get("/api/state", {{"Host", host}});
    EXPECT_EQ(r.status, 200) << "Host '" << host << "': " << r.body;
  }
}

// Host must be there once and not be empty (RFC 9112, 3.2): with two, the server checked the
// last while a proxy or browser in front of it may route by the first (the probe's two Host
// headers were answered 200).
TEST_F(SecurityTest, HostTwiceOrEmptyIsRefused) {
  const std::string good = host(), evil = "evil.example:" + std::to_string(port());
  const std::vector<Headers> cases = {{{"Host", good}, {"Host", good}},
                                      {{"Host", evil}, {"Host", good}},
                                      {{"Host", good}, {"Host", evil}},
                                      {{"Host", ""}},
                                      {{"Host", "  "}}};
  for (const Headers& h : cases) {
    const Reply r = get("/api/state", h);
    EXPECT_EQ(r.status, 400) << h.size() << " Host headers, '" << h[0].second << "': " << r.body;
    EXPECT_NE(r.body.find("Host"), std::string::npos) << r.body;
    EXPECT_EQ(r.body.find("\"document\""), std::string::npos) << r.body;
  }
  // HTTP/1.0 without a Host at all.
  const Reply none =
      fetch_raw(port(), "GET /api/state?token=" + std::string(kToken) + " HTTP/1.0\r\n\r\n", 10000);
  EXPECT_EQ(none.status, 400) << none.body;
  EXPECT_EQ(get("/api/state").status, 200);
}

// The siblings: every header whose meaning a second copy would change may appear once.
TEST_F(SecurityTest, HeadersThatMayAppearOnceAreRefusedTwice) {
  const std::string token = kToken;
  const std::vector<std::pair<std::string, Headers>> cases = {
      {"Origin", {{"Origin", "http://" + host()}, {"Origin", "http://evil.example"}}},
      {"Cookie", {{"Cookie", "anamorph_token=" + token}, {"Cookie", "anamorph_token=wrong"}}},
      {"X-Anamorph-Token", {{"X-Anamorph-Token", "wrong"}}},  // (plus the one get() adds)
      {"Content-Type", {{"Content-Type", "application/json"}, {"Content-Type", "text/plain"}}},
      {"Referer", {{"Referer", "http://" + host() + "/"}, {"Referer", "http://evil.example/"}}}};
  for (const auto& [name, h] : cases) {
    const Reply r = get("/api/state", h);
    EXPECT_EQ(r.status, 400) << name << ": " << r.body;
    EXPECT_NE(r.body.find("two " + name + " headers"), std::string::npos) << r.body;
  }
  // Content-Length twice, even with the same value (Beast takes equal ones as one).
  const std::string head =
      "POST /api/undo HTTP/1.1\r\nHost: " + host() + "\r\nX-Anamorph-Token: " + token + "\r\n";
  const Reply length =
      fetch_raw(port(), head + "Content-Length: 2\r\nContent-Length: 2\r\n\r\n{}", 10000);
  EXPECT_EQ(length.status, 400) << length.body;
  EXPECT_NE(length.body.find("two Content-Length headers"), std::string::npos) << length.body;
  // A body in a transfer coding other than chunked.
  const Reply coding =
      fetch_raw(port(), head + "Transfer-Encoding: gzip\r\nContent-Length: 2\r\n\r\n{}", 10000);
  EXPECT_TRUE(coding.status == 400 || coding.status == 0) << coding.status << coding.body;
  // List headers repeated are one list (RFC 9110, 5.3): served.
  const Reply lists = get("/api/state", {{"Accept", "application/json"}, {"Accept", "*/*"}});
  EXPECT_EQ(lists.status, 200) << lists.body;
  EXPECT_EQ(get("/api/state").status, 200);
}

// A Cookie header naming the token twice, or a query naming it twice: which one would count is a
// guess (the first cookie, the last query value), so neither is taken.
TEST_F(SecurityTest, TokenGivenTwiceInOneSourceIsRefused) {
  const std::string t = kToken;
  for (const std::string& cookies : {"anamorph_token=" + t + "; anamorph_token=wrong",
                                     "anamorph_token=wrong; anamorph_token=" + t}) {
    const Reply r = fetch(port(), {"GET", "/api/state", "", {{"Cookie", cookies}}});
    EXPECT_EQ(r.status, 400) << cookies << ": " << r.body;
    EXPECT_NE(r.body.find("anamorph_token twice"), std::string::npos) << r.body;
  }
  for (const std::string& query : {"?token=wrong&token=" + t, "?token=" + t + "&token=wrong"}) {
    const Reply r = fetch(port(), {"GET", "/api/state" + query});
    EXPECT_EQ(r.status, 400) << query << ": " << r.body;
    EXPECT_NE(r.body.find("?token= is given twice"), std::string::npos) << r.body;
  }
}

// The address the user opened wins over a cookie: every port of 127.0.0.1 shares cookies, so an
// earlier server's token (a restarted `anamorph serve`) came first and the new address got 401.
TEST_F(SecurityTest, TheAddressTokenWinsOverAnEarlierServersCookie) {
  const Reply r = fetch(port(), {"GET",
                                 "/?token=" + std::string(kToken),
                                 "",
                                 {{"Cookie", "anamorph_token=0123456789abcdef0000000000000000"}}});
  EXPECT_EQ(r.status, 200) << r.body.substr(0, 200);
  // A wrong token in the address is not saved by a right cookie either.
  const Reply wrong = fetch(
      port(),
      {"GET", "/api/state?token=wrong", "", {{"Cookie", "anamorph_token=" + std::string(kToken)}}});
  EXPECT_EQ(wrong.status, 401) << wrong.body;
}

TEST_F(SecurityTest, OriginMustBeTheServer) {
  const Reply evil = post("/api/edit", "{}", {{"Origin", "http://evil.example"}});
  EXPECT_EQ(evil.status, 403) << evil.body;
  // Another port of this machine is another origin.
  const Reply other = get("/api/state", {{"Origin", "http://127.0.0.1:1"}});
  EXPECT_EQ(other.status, 403) << other.body;
  const Reply same = get("/api/state", {{"Origin", "http://" + host()}});
  EXPECT_EQ(same.status, 200) << same.body;
  const Reply local = get("/api/state", {{"Host", "localhost:" + std::to_string(port())},
                                         {"Origin", "http://localhost:" + std::to_string(port())}});
  EXPECT_EQ(local.status, 200) << local.body;
}

TEST_F(SecurityTest, MalformedJsonIs400AndTheServerGoesOn) {
  const Reply r = post("/api/edit", std::string("{\"version\": 1, \"edits\": ["));
  EXPECT_EQ(r.status, 400) << r.body;
  ASSERT_TRUE(body_of(r).contains("error")) << r.body;
  EXPECT_FALSE(body_of(r)["error"].get<std::string>().empty()) << r.body;
  EXPECT_EQ(get("/api/state").status, 200);

  const Reply array = post("/api/edit", std::string("[1, 2]"));
  EXPECT_EQ(array.status, 400) << array.body;
  EXPECT_NE(array.body.find("object"), std::string::npos) << array.body;

  const Reply no_version = post("/api/edit", json{{"edits", json::array()}});
  EXPECT_EQ(no_version.status, 400) << no_version.body;
  EXPECT_TRUE(body_of(no_version).contains("error")) << no_version.body;
  EXPECT_EQ(version(), 1);
}

TEST_F(SecurityTest, UnknownPathIs404AndOtherMethods405) {
  const Reply unknown = get("/api/nothing");
  EXPECT_EQ(unknown.status, 404) << unknown.body;
  EXPECT_NE(unknown.body.find("/api/nothing"), std::string::npos) << unknown.body;
  const Reply put = fetch(port(), {"PUT", "/api/state", "{}", {{"X-Anamorph-Token", kToken}}});
  EXPECT_EQ(put.status, 405) << put.body;
  EXPECT_EQ(fetch(port(), {"DELETE", "/api/edit", "", {{"X-Anamorph-Token", kToken}}}).status, 405);
}

TEST_F(SecurityTest, GarbageInsteadOfHttpIsAnsweredOrClosed) {
  const std::string garbage =
      "\x16\x03\x01\x02\x00\x01\x00\x01\xfc\x03\x03 not http at all\r\n\r\n"s;
  const Reply r = fetch_raw(port(), garbage, 10000);
  EXPECT_TRUE(r.status == 400 || r.status == 0) << r.status << " " << r.body;
  const Reply bad_length = fetch_raw(
      port(), "GET / HTTP/1.1\r\nHost: " + host() + "\r\nContent-Length: many\r\n\r\n", 10000);
  EXPECT_TRUE(bad_length.status == 400 || bad_length.status == 0) << bad_length.status;
  EXPECT_EQ(get("/api/state").status, 200);
}

TEST_F(SecurityTest, BodyOverTheLimitIs413) {
  // Only the header is sent: its Content-Length alone is over the limit, and the server answers
  // before any body (a body the server never reads would make its close a reset).
  const size_t limit = server::HttpOptions{}.max_body;
  const Reply r = fetch_raw(port(), "POST /api/edit HTTP/1.1\r\nHost: " + host() +
                                        "\r\nX-Anamorph-Token: " + kToken +
                                        "\r\nContent-Type: application/json\r\nContent-Length: " +
                                        std::to_string(limit + 1) + "\r\n\r\n");
  EXPECT_EQ(r.status, 413) << r.body;
  // At the limit itself the body is read (and, not being JSON, refused as such).
  const Reply at = post("/api/edit", std::string(limit, ' '));
  EXPECT_EQ(at.status, 400) << at.body.substr(0, 200);
  EXPECT_EQ(get("/api/state").status, 200);
}

TEST_F(SecurityTest, BadPercentEncodingIs400) {
  for (const std::string target : {"/api/st%zzate", "/api/state?after=%4", "/api/state%", "/%g0"}) {
    const Reply r = get(target);
    EXPECT_EQ(r.status, 400) << target << ": " << r.body;
  }
  EXPECT_EQ(get("/api/st%61te").status, 200);  // (a good escape: 'a')
}

TEST_F(SecurityTest, KeepAliveConnectionServesSeveralRequests) {
  Connection c(port());
  for (int i = 0; i < 3; ++i) {
    c.send({"GET", "/api/state", "", {{"X-Anamorph-Token", kToken}}, true});
    const Reply r = c.receive();
    EXPECT_EQ(r.status, 200) << "request " << i << ": " << r.body;
  }
}

}  // namespace
}  // namespace anamorph::test
