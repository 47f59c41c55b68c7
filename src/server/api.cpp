#include "server/api.h"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <random>

#include "io/json_nesting.h"
#include "io/read_file.h"
#include "scene/declarations.h"
#include "scene/scene_schema.h"
#include "server/web_assets.h"

namespace anamorph::server {

namespace {

HttpResponse json_response(int status, const Json& j) {
  HttpResponse r;
  r.status = status;
  // (A message may quote the request's bytes, which need not be UTF-8: replaced, not thrown.)
  r.body = j.dump(-1, ' ', false, Json::error_handler_t::replace);
  return r;
}

HttpResponse error(int status, const std::string& message, const std::string& key = {}) {
  Json j = {{"error", message}};
  if (!key.empty()) j["key"] = key;
  return json_response(status, j);
}

// A JSON value as TOML text (the scene reader then checks it against the key's declaration).
std::string toml_text(const Json& v) {
  if (v.is_array()) {
    std::string s = "[";
    for (size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + toml_text(v[i]);
    return s + "]";
  }
  if (v.is_object()) {
    std::string s = "{ ";
    bool first = true;
    for (const auto& [k, e] : v.items()) {
      s += (first ? "" : ", ") + Json(k).dump() + " = " + toml_text(e);
      first = false;
    }
    return s + " }";
  }
  if (v.is_number_float() && !std::isfinite(v.get<double>()))
    throw std::invalid_argument("numbers must be finite");
  if (v.is_null()) throw std::invalid_argument("null is only allowed as a whole edit's value");
  return v.dump();  // numbers, booleans, strings (JSON's escapes are TOML's)
}

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

const Json& field(const Json& body, const char* name) {
  static const Json none;
  auto it = body.find(name);
  return it == body.end() ? none : *it;
}

double number_in(const Json& body, const char* name, double lo, double hi) {
  const Json& v = field(body, name);
  if (!v.is_number()) throw std::invalid_argument(fmt::format("'{}' must be a number", name));
  const double x = v.get<double>();
  if (!(x >= lo && x <= hi))
    throw std::invalid_argument(fmt::format("'{}' must be in [{}, {}] (got {})", name, lo, hi, x));
  return x;
}

Json vec3_json(const Vec3& v) { return Json::array({v.x, v.y, v.z}); }

// ?name= as a finite number, all of its text ("12abc" is not 12), or `fallback` when absent.
double query_number(const HttpRequest& q, const char* name, double fallback) {
  const auto it = q.query.find(name);
  if (it == q.query.end()) return fallback;
  const std::string& t = it->second;
  double x = 0;
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), x);
  if (t.empty() || ec != std::errc() || end != t.data() + t.size() || !std::isfinite(x))
    throw std::invalid_argument(std::string("?") + name + "= takes a number (got '" + t + "')");
  return x;
}

// ?name= as a whole number in [lo, hi].
int64_t query_integer(const HttpRequest& q, const char* name, int64_t fallback, int64_t lo,
                      int64_t hi) {
  const double x = query_number(q, name, double(fallback));
  if (x != std::floor(x) || x < double(lo) || x > double(hi))
    throw std::invalid_argument(std::string("?") + name + "= takes a whole number in [" +
                                std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return int64_t(x);
}

int64_t query_version(const HttpRequest& q) {
  return query_integer(q, "version", 0, 0, int64_t(1) << 53);
}

// The outcome with the document's state after it (the page needs no second request).
HttpResponse outcome_response(const EditOutcome& o, const Editor& editor) {
  if (o.error) {
    Json j = {{"error", o.error->message}, {"version", o.version}};
    if (!o.error->key.empty()) j["key"] = o.error->key;
    return json_response(o.error->status, j);
  }
  return json_response(
      200, {{"version", o.version}, {"warnings", o.warnings}, {"state", editor.state()}});
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
  const std::string port = ":" + std::to_string(opt_.port);
  const bool loopback = opt_.host == "127.0.0.1" || opt_.host == "::1";
  const std::string host = q.header("host");
  const bool host_ok = !loopback || host == "127.0.0.1" + port || host == "localhost" + port ||
                       host == "[::1]" + port;
  if (!host_ok)
    return error(403, "this server answers only to http://127.0.0.1" + port +
                          " (the Host header named '" + host + "')");
  const std::string origin = q.header("origin");
  if (!origin.empty() && origin != "http://" + host)
    return error(403, "cross-origin requests are refused (Origin '" + origin + "')");
  bool twice = false;
  const std::string cookie = cookie_token(q.header("cookie"), &twice);
  if (twice) return error(400, "the Cookie header names anamorph_token twice");
  // The most explicit wins: the header a script sets, then the address the user opened (the
  // cookie may be an earlier server's: every port of 127.0.0.1 shares it), then the cookie.
  std::string token = q.header("x-anamorph-token");
  if (token.empty() && q.query.count("token")) token = q.query.at("token");
  if (token.empty()) token = cookie;
  if (!equal_secret(token, opt_.token))
    return error(401, "missing or wrong token: open the address `anamorph serve` printed");
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
      r = error(400, std::string("malformed JSON: ") + e.what());
    } catch (const std::invalid_argument& e) {
      r = error(400, e.what());
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
  if (q.method != "GET") return error(405, "the page is read with GET");
  const std::string path = q.path == "/" ? "/index.html" : q.path;
  const WebAsset* a = find_web_asset(path);
  if (!a) return error(404, "no such page: " + q.path);
  HttpResponse r;
  r.content_type = std::string(a->content_type);
  if (opt_.web_folder.empty()) {
    r.body = std::string(a->bytes);
  } else {  // (developers: edit web/ and reload, without building)
    std::vector<unsigned char> bytes;
    if (const auto failure = read_whole_file(opt_.web_folder + path, &bytes, kTextInput))
      return error(404, describe(*failure, opt_.web_folder + path));
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

HttpResponse Api::route_api(const HttpRequest& q, const std::function<bool()>& client_gone) {
  const std::string& p = q.path;
  const bool get = q.method == "GET", post = q.method == "POST";
  if (!get && !post) return error(405, "the API takes GET and POST");
  if (const std::string e = json_nesting_error(q.body); !e.empty())
    throw std::invalid_argument("the body is " + e);
  const Json body = post && !q.body.empty() ? Json::parse(q.body) : Json::object();
  if (!body.is_object()) throw std::invalid_argument("the body must be a JSON object");

  if (get && p == "/api/declarations") return json_response(200, declarations_json());
  if (get && p == "/api/state") return json_response(200, editor_.state());
  if (post && p == "/api/edit") {
    const Json& edits = field(body, "edits");
    if (!field(body, "version").is_number_integer() || !edits.is_array())
      throw std::invalid_argument(
          "an edit is {\"version\": N, \"edits\": [{\"key\", \"value\" or \"toml\"}]}");
    std::vector<KeyEdit> list;
    for (const Json& e : edits) {
      if (!e.is_object() || !field(e, "key").is_string())
        throw std::invalid_argument("each edit needs a \"key\" (a dotted key, a string)");
      KeyEdit k{field(e, "key").get<std::string>(), std::nullopt};
      if (field(e, "toml").is_string())  // the value as TOML text, written by hand
        k.value = field(e, "toml").get<std::string>();
      else if (!field(e, "value").is_null())
        k.value = toml_text(field(e, "value"));
      list.push_back(std::move(k));
    }
    return outcome_response(editor_.edit(list, field(body, "version").get<int64_t>()), editor_);
  }
  if (post && p == "/api/undo") return outcome_response(editor_.undo(), editor_);
  if (post && p == "/api/redo") return outcome_response(editor_.redo(), editor_);
  if (post && p == "/api/time")
    return outcome_response(editor_.set_frame(number_in(body, "frame", -1e9, 1e9)), editor_);
  if (get && p == "/api/frame") return frame(q, client_gone);
  if (p == "/api/preview") {
    PreviewSettings s = editor_.preview().settings();
    if (post) {
      if (body.contains("integrator")) {
        const Json& v = field(body, "integrator");
        if (v.is_null() || v == "scene") {
          s.integrator.reset();
        } else {
          const auto names = integrator_names();
          const auto it = std::find(names.begin(), names.end(), v.get<std::string>());
          if (it == names.end()) throw std::invalid_argument("unknown integrator " + v.dump());
          s.integrator = IntegratorKind(it - names.begin());
        }
      }
      if (body.contains("max_spp")) s.max_spp = int(number_in(body, "max_spp", 1, 4096));
      if (body.contains("max_width")) s.max_width = int(number_in(body, "max_width", 16, 4096));
      if (body.contains("max_height")) s.max_height = int(number_in(body, "max_height", 16, 4096));
      editor_.preview().set_settings(s);
    }
    return json_response(
        200, {{"integrator", s.integrator ? std::string(name_of(*s.integrator)) : "scene"},
              {"max_spp", s.max_spp},
              {"max_width", s.max_width},
              {"max_height", s.max_height}});
  }
  if (post && p == "/api/pick") {
    const Vec2 uv{number_in(body, "u", 0, 1), number_in(body, "v", 0, 1)};
    const auto r = editor_.pick(
        uv, field(body, "version").is_number_integer() ? field(body, "version").get<int64_t>() : 0);
    if (!r) return error(503, "the preview is not ready");
    Json j = {{"ray", r->ray}, {"hit", r->hit}};
    if (r->hit) {
      j["position"] = vec3_json(r->position);
      j["normal"] = vec3_json(r->normal);
      j["distance"] = r->distance;
      j["object"] = r->object;
    }
    return json_response(200, j);
  }
  if (post && p == "/api/project") {
    const Json& pos = field(body, "position");
    if (!pos.is_array() || pos.size() != 3 || !pos[0].is_number() || !pos[1].is_number() ||
        !pos[2].is_number())
      throw std::invalid_argument("'position' must be [x, y, z]");
    const auto uvs = editor_.project(
        {pos[0].get<double>(), pos[1].get<double>(), pos[2].get<double>()},
        field(body, "version").is_number_integer() ? field(body, "version").get<int64_t>() : 0);
    if (!uvs) return error(503, "the preview is not ready");
    Json l = Json::array();
    for (const Vec2& uv : *uvs) l.push_back({uv.x, uv.y});
    return json_response(200, {{"uv", l}});
  }
  if (get && p == "/api/coins") {
    const auto sites = editor_.coins(query_version(q));
    if (!sites) return error(503, "the preview is not ready");
    Json l = Json::array();
    for (const CoinSite& c : *sites)
      l.push_back({{"coin", c.coin},
                   {"uv", {c.uv.x, c.uv.y}},
                   {"radius", c.radius},
                   {"strength", c.strength},
                   {"stiffness", c.stiffness}});
    return json_response(200, {{"sites", l}});
  }
  if (get && p == "/api/magnification") {
    if (!q.query.count("width") || !q.query.count("height"))
      throw std::invalid_argument("?width= and ?height= must be in [1, 1024]");
    const int w = int(query_integer(q, "width", 0, 1, 1024));
    const int h = int(query_integer(q, "height", 0, 1, 1024));
    const auto m = editor_.magnification(w, h, query_version(q));
    if (!m) return error(503, "the preview is not ready");
    HttpResponse r;
    r.content_type = "application/octet-stream";  // float32, little-endian, row by row
    r.body.assign(reinterpret_cast<const char*>(m->data()), m->size() * sizeof(float));
    return r;
  }
  if (get && p == "/api/rays") {
    const int nu = int(std::clamp(query_number(q, "nu", 24), 1.0, 256.0));
    const int nv = int(std::clamp(query_number(q, "nv", 14), 1.0, 256.0));
    const auto o = editor_.ray_overview(nu, nv, query_version(q));
    if (!o) return error(503, "the preview is not ready");
    Json org = Json::array(), dir = Json::array(), boxes = Json::array();
    for (size_t i = 0; i < o->org.size(); ++i) {
      org.push_back(o->valid[i] ? vec3_json(o->org[i]) : Json(nullptr));
      dir.push_back(o->valid[i] ? vec3_json(o->dir[i]) : Json(nullptr));
    }
    for (const Bounds3& b : o->boxes) boxes.push_back({vec3_json(b.lo), vec3_json(b.hi)});
    return json_response(200,
                         {{"nu", nu}, {"nv", nv}, {"org", org}, {"dir", dir}, {"boxes", boxes}});
  }
  if (post && p == "/api/save") {
    const Json& name = field(body, "name");
    if (!name.is_null() && !name.is_string()) throw std::invalid_argument("'name' is a file name");
    const Editor::SaveOutcome saved = editor_.save(name.is_string() ? name.get<std::string>() : "");
    if (saved.error) return error(400, *saved.error);
    return json_response(200,
                         {{"saved", name.is_string() ? name.get<std::string>()
                                                     : editor_.scene_file().filename().string()},
                          {"normalized", saved.normalized}});
  }
  if (post && p == "/api/render") {
    Editor::RenderRequest req;
    if (field(body, "png").is_boolean()) req.png = field(body, "png").get<bool>();
    if (field(body, "exr").is_boolean()) req.exr = field(body, "exr").get<bool>();
    const Json& frames = field(body, "frames");
    if (!frames.is_null()) {
      if (!frames.is_array() || frames.size() != 2 || !frames[0].is_number_integer() ||
          !frames[1].is_number_integer())
        throw std::invalid_argument("'frames' is [first, last]");
      req.frames = std::pair{frames[0].get<int>(), frames[1].get<int>()};
    }
    if (!req.png && !req.exr) throw std::invalid_argument("ask for a PNG, an EXR or both");
    if (req.frames && (req.frames->first < 0 || req.frames->first > req.frames->second ||
                       req.frames->second - req.frames->first > 100000))
      throw std::invalid_argument("'frames' go from a first to a last frame (0 <= first <= last)");
    if (auto why = editor_.start_render(req)) return error(409, *why);  // (one is running)
    return json_response(200, editor_.render_status());
  }
  if (get && p == "/api/render") return json_response(200, editor_.render_status());
  if (post && p == "/api/render/cancel") {
    if (!editor_.cancel_render()) return error(409, "no render is running");
    return json_response(200, editor_.render_status());
  }
  if (get && (p == "/api/render/result.png" || p == "/api/render/result.exr")) {
    const std::string ext = p.substr(p.size() - 3);
    std::optional<int> frame;
    if (q.query.count("frame")) frame = int(std::clamp(query_number(q, "frame", 0), -1e9, 1e9));
    const auto file = editor_.render_result(ext, frame);
    if (!file) return error(404, "no finished render with a " + ext + " file");
    HttpResponse r;
    r.content_type = ext == "png" ? "image/png" : "image/x-exr";
    r.file = *file;
    r.headers.emplace_back("Content-Disposition",
                           "attachment; filename=\"" + file->filename().string() + "\"");
    return r;
  }
  return error(404, "no such API call: " + q.method + " " + p);
}

// The newest preview frame after ?after=SEQ, waiting up to ?timeout= seconds (default 20) for one:
// 8-bit RGBA with its size and what it shows in headers; 204 when none came.
HttpResponse Api::frame(const HttpRequest& q, const std::function<bool()>& client_gone) {
  const auto after = uint64_t(query_integer(q, "after", 0, 0, int64_t(1) << 53));
  const double timeout = std::clamp(query_number(q, "timeout", 20), 0.0, 60.0);
  const auto f = editor_.preview().wait_frame(after, timeout, client_gone);
  HttpResponse r;
  if (!f) {
    r.status = 204;
    return r;
  }
  r.content_type = "application/octet-stream";
  r.shared_body = std::shared_ptr<const std::string>(f, &f->rgba);  // (no copy of the frame)
  r.headers = {{"X-Frame-Seq", std::to_string(f->seq)},
               {"X-Frame-Version", std::to_string(f->version)},
               {"X-Frame-Width", std::to_string(f->width)},
               {"X-Frame-Height", std::to_string(f->height)},
               {"X-Frame-Pass", std::to_string(f->pass)},
               {"X-Frame-Passes", std::to_string(f->passes)},
               {"X-Frame-Coarse", f->coarse ? "1" : "0"},
               {"X-Frame-Seconds", fmt::format("{:.4f}", f->seconds)}};
  return r;
}

}  // namespace anamorph::server
