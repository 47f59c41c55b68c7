#include "server/api.h"

#include <fmt/format.h>

#include <algorithm>
#include <random>

#include "io/read_file.h"
#include "server/api_json.h"
#include "server/web_assets.h"

namespace anamorph::server {

namespace {

bool equal_secret(const std::string& a, const std::string& b) {
  if (a.size() != b.size()) return false;
  unsigned char d = 0;
  for (size_t i = 0; i < a.size(); ++i) d |= static_cast<unsigned char>(a[i] ^ b[i]);
  return d == 0;
}

// The anamorph_token cookie's value ("" when there is none); `*twice` when it is there twice
// (two values: which one would count is anyone's guess, so such a request is refused).
std::string cookie_token(const std::string& cookies, bool* twice) {
  const std::string name = "anamorph_token=";
  std::string found;
  int count = 0;
  for (size_t s = 0; s < cookies.size();) {
    while (s < cookies.size() && cookies[s] == ' ') ++s;
    size_t e = cookies.find(';', s);
    if (e == std::string::npos) e = cookies.size();
    if (cookies.compare(s, name.size(), name) == 0 && count++ == 0)
      found = cookies.substr(s + name.size(), e - s - name.size());
    s = e + 1;
  }
  *twice = count > 1;
  return found;
}

}  // namespace

std::string new_token() {
  std::random_device rd;
  std::string t;
  for (int i = 0; i < 4; ++i) t += fmt::format("{:08x}", rd());
  return t;
}

// Why `q` may not be served, as the response to give, or none.
std::optional<HttpResponse> Api::refuse(const HttpRequest& q) const {
  const std::string port =
      fmt::format(":{}", opt_.port);  // (not ":" + to_string: GCC 12 -Wrestrict)
  const bool loopback = opt_.host == "127.0.0.1" || opt_.host == "::1";
  const std::string host = q.header("host");
  const bool host_ok = !loopback || host == "127.0.0.1" + port || host == "localhost" + port ||
                       host == "[::1]" + port;
  if (!host_ok)
    return error_response(403, "this server answers only to http://127.0.0.1" + port +
                                   " (the Host header named '" + host + "')");
  const std::string origin = q.header("origin");
  if (!origin.empty() && origin != "http://" + host)
    return error_response(403, "cross-origin requests are refused (Origin '" + origin + "')");
  bool twice = false;
  const std::string cookie = cookie_token(q.header("cookie"), &twice);
  if (twice) return error_response(400, "the Cookie header names anamorph_token twice");
  // The most explicit wins: the header a script sets, then the address the user opened (the
  // cookie may be an earlier server's: every port of 127.0.0.1 shares it), then the cookie.
  std::string token = q.header("x-anamorph-token");
  if (token.empty() && q.query.count("token")) token = q.query.at("token");
  if (token.empty()) token = cookie;
  if (!equal_secret(token, opt_.token))
    return error_response(401, "missing or wrong token: open the address `anamorph serve` printed");
  return std::nullopt;
}

HttpResponse Api::handle(const HttpRequest& q, const std::function<bool()>& client_gone) {
  HttpResponse r;
  if (auto no = refuse(q)) {
    r = *no;
  } else if (q.path.rfind("/api/", 0) == 0) {
    try {
      r = route_api(q, client_gone);
    } catch (const Json::exception& e) {
      r = error_response(400, std::string("malformed JSON: ") + e.what());
    } catch (const std::invalid_argument& e) {
      r = error_response(400, e.what());
    }
  } else {
    r = page(q);
  }
  r.headers.emplace_back("Cache-Control", "no-store");
  r.headers.emplace_back("X-Content-Type-Options", "nosniff");
  r.headers.emplace_back("X-Frame-Options", "DENY");
  r.headers.emplace_back("Referrer-Policy", "no-referrer");
  return r;
}

HttpResponse Api::page(const HttpRequest& q) const {
  if (q.method != "GET") return error_response(405, "the page is read with GET");
  const std::string path = q.path == "/" ? "/index.html" : q.path;
  const WebAsset* a = find_web_asset(path);
  if (!a) return error_response(404, "no such page: " + q.path);
  HttpResponse r;
  r.content_type = std::string(a->content_type);
  if (opt_.web_folder.empty()) {
    r.body = std::string(a->bytes);
  } else {  // (developers: edit web/ and reload, without building)
    std::vector<unsigned char> bytes;
    if (const auto failure = read_whole_file(opt_.web_folder + path, &bytes, kTextInput))
      return error_response(404, describe(*failure, opt_.web_folder + path));
    r.body.assign(bytes.begin(), bytes.end());
  }
  if (path == "/index.html") {
    // The page's later requests (scripts, API) carry the token in this cookie, which the browser
    // never sends along with another site's requests.
    r.headers.emplace_back("Set-Cookie",
                           "anamorph_token=" + opt_.token + "; Path=/; HttpOnly; SameSite=Strict");
    r.headers.emplace_back("Content-Security-Policy",
                           "default-src 'self'; img-src 'self' blob: data:; "
                           "style-src 'self'; script-src 'self'; connect-src 'self'");
  }
  return r;
}

}  // namespace anamorph::server
