// Bad query strings for the camera views and the preview's frames: random ones (a fixed seed)
// get an answer, never a crash or a hang, and the server goes on serving.
#include "server_fixture.h"

#include <future>
#include <random>
#include <set>

namespace anamorph::test {
namespace {

using QueryFuzzTest = ServerTest;

// A query string of up to 5 parameters drawn from the names the endpoints read (and others),
// with values that are numbers, edge cases, non-numbers and percent-escapes. Waits are bounded:
// `timeout` is always given for /api/frame and stays below 0.1 s, and `version` never names a
// version after the current one (which would wait 10 s for it).
std::string random_query(std::mt19937& rng, bool frame) {
  static const std::vector<std::string> names = {"nu",    "nv",   "width",   "height", "version",
                                                 "after", "n%75", "wid%74h", "x",      "",
                                                 "token", "nu[]", "%00",     "%zz",    "timeout%"};
  static const std::vector<std::string> values = {"",           "0",
                                                  "1",          "-1",
                                                  "2",          "3",
                                                  "17",         "24",
                                                  "256",        "257",
                                                  "1024",       "1025",
                                                  "2000",       "-2147483649",
                                                  "2147483648", "nan",
                                                  "NaN",        "inf",
                                                  "-inf",       "1e308",
                                                  "1e999",      "-1e999",
                                                  "abc",        "0x10",
                                                  "1.5",        "%20%207",
                                                  "%2B3",       "%2D0",
                                                  "%00",        "%zz",
                                                  "%",          "1%00",
                                                  "9e9",        "99999999999999999999",
                                                  "+",          "-",
                                                  ".",          "e",
                                                  "%E2%82%AC",  "1e-320"};
  static const std::vector<std::string> versions = {
      "0", "1", "-5", "abc", "1e3", "0x1", "", "99999999999999999999", "-9223372036854775808"};
  static const std::vector<std::string> timeouts = {"0",    "0.01", "-5",   "nan", "abc",
                                                    "1e-9", "",     "-inf", "0.05"};
  std::uniform_int_distribution<size_t> count(0, 5);
  auto pick = [&](const std::vector<std::string>& l) {
    return l[std::uniform_int_distribution<size_t>(0, l.size() - 1)(rng)];
  };
  std::string q;
  const size_t n = count(rng);
  for (size_t i = 0; i < n; ++i) {
    const std::string name = pick(names);
    const std::string value = name == "version" ? pick(versions) : pick(values);
    q += (q.empty() ? "" : "&") + name + (rng() % 8 == 0 ? "" : "=" + value);
  }
  if (frame) {  // (appended piece by piece: GCC 12 warns, wrongly, of an overlapping copy in
                //  `const char* + std::string&&`)
    if (!q.empty()) q += '&';
    q += "timeout=";
    q += pick(timeouts);
  }
  return q;
}

TEST_F(QueryFuzzTest, RandomQueriesGetAnAnswerAndTheServerGoesOn) {
  std::mt19937 rng(20261125);
  const std::vector<std::string> paths = {"/api/rays", "/api/magnification", "/api/coins",
                                          "/api/frame"};
  const std::set<int> allowed = {200, 204, 400, 503};
  std::map<int, int> seen;
  int api_refusals = 0;
  for (int i = 0; i < 200; ++i) {
    const std::string& path = paths[rng() % paths.size()];
    const std::string target = path + "?" + random_query(rng, path == "/api/frame");
    const Reply r = get(target);
    ++seen[r.status];
    ASSERT_TRUE(allowed.count(r.status))
        << "#" << i << " " << target << ": " << r.status << " " << r.body.substr(0, 200);
    if (r.status == 400) {
      // With a message: the API's as JSON, the HTTP layer's (a malformed URL) as text.
      EXPECT_FALSE(r.body.empty()) << target;
      if (r.header("content-type") == "application/json") {
        EXPECT_TRUE(body_of(r)["error"].is_string()) << target << ": " << r.body;
        ++api_refusals;
      }
    }
    if (r.status == 200 && path == "/api/magnification") {
      // float32s, at least one
      EXPECT_EQ(r.body.size() % 4, 0u) << target;
      EXPECT_GE(r.body.size(), 4u) << target;
    }
    if (r.status == 200 && path == "/api/rays") {
      const json b = body_of(r);
      ASSERT_TRUE(b.is_object()) << target;
      EXPECT_EQ(b["org"].size(), b["nu"].get<size_t>() * b["nv"].get<size_t>()) << target;
      EXPECT_GE(b["nu"].get<int>(), 1) << target;
      EXPECT_LE(b["nu"].get<int>(), 256) << target;
    }
  }
  // Both answers and refusals came (the loop reached the endpoints' code, not only the router).
  EXPECT_GT(seen[200], 10);
  EXPECT_GT(api_refusals, 10) << seen[400] << " refusals in all";
  // Still serving, and still right.
  const Reply s = get("/api/state");
  EXPECT_EQ(s.status, 200) << s.body.substr(0, 200);
  const Reply r = get("/api/rays?nu=3&nv=3");
  ASSERT_EQ(r.status, 200) << r.body.substr(0, 200);
  EXPECT_EQ(body_of(r)["dir"].size(), 9u);
  const Reply m = get("/api/magnification?width=4&height=3");
  ASSERT_EQ(m.status, 200) << m.body.substr(0, 200);
  EXPECT_EQ(m.body.size(), 48u);
  EXPECT_TRUE(eventually([&] { return http->connections() == 0; }, 10)) << http->connections();
}

TEST_F(QueryFuzzTest, AVersionNotYetShownIs503AfterTheWait) {
  // A version after the document's never comes: the camera views wait for it (10 s) and give up.
  const int64_t future = version() + 5;
  const std::string v = "version=" + std::to_string(future);
  // (in parallel: each waits 10 s)
  auto ask = [&](const std::string& target) {
    return std::async(std::launch::async, [this, target] { return get(target).status; });
  };
  auto rays = ask("/api/rays?nu=2&nv=2&" + v);
  auto coins = ask("/api/coins?" + v);
  auto mag = ask("/api/magnification?width=2&height=2&" + v);
  auto pick = std::async(std::launch::async, [&] {
    return post("/api/pick", json{{"u", 0.5}, {"v", 0.5}, {"version", future}}).status;
  });
  EXPECT_EQ(rays.get(), 503);
  EXPECT_EQ(coins.get(), 503);
  EXPECT_EQ(mag.get(), 503);
  EXPECT_EQ(pick.get(), 503);
  EXPECT_EQ(get("/api/state").status, 200);
}

}  // namespace
}  // namespace anamorph::test
