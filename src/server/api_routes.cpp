// The API's calls: a route table of (method, path, handler), one handler a call. A new call is its
// handler and its line in kRoutes.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "io/image_sink.h"
#include "io/json_nesting.h"
#include "scene/declarations.h"
#include "scene/scene_schema.h"
#include "server/api.h"
#include "server/api_json.h"

namespace anamorph::server {

namespace {

// What a handler gets: the request, its body parsed (an object; {} for a GET), and whether the
// client has gone (for calls that wait).
struct ApiCall {
  const HttpRequest& q;
  const Json& body;
  const std::function<bool()>& client_gone;
};
using Handler = HttpResponse (*)(Editor&, const ApiCall&);

int64_t body_version(const Json& body) {
  return field(body, "version").is_number_integer() ? field(body, "version").get<int64_t>() : 0;
}

HttpResponse declarations(Editor&, const ApiCall&) {
  return json_response(200, declarations_json());
}

HttpResponse state(Editor& ed, const ApiCall&) { return json_response(200, ed.state()); }

HttpResponse edit(Editor& ed, const ApiCall& c) {
  const Json& edits = field(c.body, "edits");
  if (!field(c.body, "version").is_number_integer() || !edits.is_array())
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
  return outcome_response(ed.edit(list, field(c.body, "version").get<int64_t>()), ed);
}

HttpResponse undo(Editor& ed, const ApiCall&) { return outcome_response(ed.undo(), ed); }
HttpResponse redo(Editor& ed, const ApiCall&) { return outcome_response(ed.redo(), ed); }

HttpResponse set_time(Editor& ed, const ApiCall& c) {
  return outcome_response(ed.set_frame(number_in(c.body, "frame", -1e9, 1e9)), ed);
}

// The newest preview frame after ?after=SEQ, waiting up to ?timeout= seconds (default 20) for one:
// 8-bit RGBA with its size and what it shows in headers; 204 when none came.
HttpResponse frame(Editor& ed, const ApiCall& c) {
  const auto after = uint64_t(query_integer(c.q, "after", 0, 0, int64_t(1) << 53));
  const double timeout = std::clamp(query_number(c.q, "timeout", 20), 0.0, 60.0);
  const auto f = ed.preview().wait_frame(after, timeout, c.client_gone);
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
               {"X-Frame-Denoised", f->denoised ? "1" : "0"},
               {"X-Frame-Seconds", fmt::format("{:.4f}", f->seconds)}};
  return r;
}

// The preview's settings, changed by a POST.
HttpResponse preview(Editor& ed, const ApiCall& c) {
  PreviewSettings s = ed.preview().settings();
  const Json& body = c.body;
  if (c.q.method == "POST") {
    if (body.contains("integrator")) {
      const Json& v = field(body, "integrator");
      if (v.is_null() || v == "scene") {
        s.integrator.reset();
      } else {
        const auto names = integrator_names();
        const auto it = std::find(names.begin(), names.end(), v.get<std::string>());
        if (it == names.end()) throw std::invalid_argument("unknown integrator " + v.dump());
        s.integrator = std::string(*it);
      }
    }
    if (body.contains("denoise")) {
      const Json& v = field(body, "denoise");
      if (!v.is_boolean()) throw std::invalid_argument("denoise: expected true or false");
      s.denoise = v.get<bool>();
    }
    if (body.contains("max_spp")) s.max_spp = int(number_in(body, "max_spp", 1, 4096));
    if (body.contains("max_width")) s.max_width = int(number_in(body, "max_width", 16, 4096));
    if (body.contains("max_height")) s.max_height = int(number_in(body, "max_height", 16, 4096));
    ed.preview().set_settings(s);
  }
  return json_response(200, {{"integrator", s.integrator ? *s.integrator : "scene"},
                             {"max_spp", s.max_spp},
                             {"denoise", s.denoise},
                             {"max_width", s.max_width},
                             {"max_height", s.max_height}});
}

HttpResponse pick(Editor& ed, const ApiCall& c) {
  const Vec2 uv{number_in(c.body, "u", 0, 1), number_in(c.body, "v", 0, 1)};
  const auto r = ed.pick(uv, body_version(c.body));
  if (!r) return error_response(503, "the preview is not ready");
  Json j = {{"ray", r->ray}, {"hit", r->hit}};
  if (r->hit) {
    j["position"] = vec3_json(r->position);
    j["normal"] = vec3_json(r->normal);
    j["distance"] = r->distance;
    j["object"] = r->object;
    if (!r->box.empty()) j["box"] = {vec3_json(r->box.lo), vec3_json(r->box.hi)};
  }
  return json_response(200, j);
}

HttpResponse project(Editor& ed, const ApiCall& c) {
  const Json& pos = field(c.body, "position");
  if (!pos.is_array() || pos.size() != 3 || !pos[0].is_number() || !pos[1].is_number() ||
      !pos[2].is_number())
    throw std::invalid_argument("'position' must be [x, y, z]");
  const auto uvs = ed.project({pos[0].get<double>(), pos[1].get<double>(), pos[2].get<double>()},
                              body_version(c.body));
  if (!uvs) return error_response(503, "the preview is not ready");
  Json l = Json::array();
  for (const Vec2& uv : *uvs) l.push_back({uv.x, uv.y});
  return json_response(200, {{"uv", l}});
}

HttpResponse coins(Editor& ed, const ApiCall& c) {
  const auto sites = ed.coins(query_version(c.q));
  if (!sites) return error_response(503, "the preview is not ready");
  Json l = Json::array();
  for (const CoinSite& s : *sites)
    l.push_back({{"coin", s.coin},
                 {"uv", {s.uv.x, s.uv.y}},
                 {"radius", s.radius},
                 {"strength", s.strength},
                 {"stiffness", s.stiffness}});
  return json_response(200, {{"sites", l}});
}

HttpResponse magnification(Editor& ed, const ApiCall& c) {
  if (!c.q.query.count("width") || !c.q.query.count("height"))
    throw std::invalid_argument("?width= and ?height= must be in [1, 1024]");
  const int w = int(query_integer(c.q, "width", 0, 1, 1024));
  const int h = int(query_integer(c.q, "height", 0, 1, 1024));
  const auto m = ed.magnification(w, h, query_version(c.q));
  if (!m) return error_response(503, "the preview is not ready");
  HttpResponse r;
  r.content_type = "application/octet-stream";  // float32, little-endian, row by row
  r.body.assign(reinterpret_cast<const char*>(m->data()), m->size() * sizeof(float));
  return r;
}

HttpResponse rays(Editor& ed, const ApiCall& c) {
  const int nu = int(std::clamp(query_number(c.q, "nu", 24), 1.0, 256.0));
  const int nv = int(std::clamp(query_number(c.q, "nv", 14), 1.0, 256.0));
  const auto o = ed.ray_overview(nu, nv, query_version(c.q));
  if (!o) return error_response(503, "the preview is not ready");
  Json org = Json::array(), dir = Json::array(), boxes = Json::array();
  for (size_t i = 0; i < o->org.size(); ++i) {
    org.push_back(o->valid[i] ? vec3_json(o->org[i]) : Json(nullptr));
    dir.push_back(o->valid[i] ? vec3_json(o->dir[i]) : Json(nullptr));
  }
  for (const Bounds3& b : o->boxes) boxes.push_back({vec3_json(b.lo), vec3_json(b.hi)});
  return json_response(200, {{"nu", nu}, {"nv", nv}, {"org", org}, {"dir", dir}, {"boxes", boxes}});
}

HttpResponse save(Editor& ed, const ApiCall& c) {
  const Json& name = field(c.body, "name");
  if (!name.is_null() && !name.is_string()) throw std::invalid_argument("'name' is a file name");
  const Editor::SaveOutcome saved = ed.save(name.is_string() ? name.get<std::string>() : "");
  if (saved.error) return error_response(400, *saved.error);
  return json_response(200, {{"saved", name.is_string() ? name.get<std::string>()
                                                        : ed.scene_file().filename().string()},
                             {"normalized", saved.normalized}});
}

// The file formats asked for: "formats": [names of sink kinds], or one boolean per kind named
// for it ({"png": true, "exr": true}, the older form); none: the editor's default (the first).
std::vector<std::string> requested_formats(const Json& body) {
  const Json& formats = field(body, "formats");
  std::vector<std::string> names;
  if (!formats.is_null()) {
    if (!formats.is_array()) throw std::invalid_argument("'formats' is a list of names");
    for (const Json& f : formats) {
      if (!f.is_string()) throw std::invalid_argument("'formats' is a list of names");
      names.push_back(f.get<std::string>());
    }
    if (names.empty()) throw std::invalid_argument("'formats' names no file format");
    return names;
  }
  bool any_named = false;
  for (const SinkKind* k : sink_kinds()) {
    const Json& b = field(body, k->name.c_str());
    if (!b.is_boolean()) continue;
    any_named = true;
    if (b.get<bool>()) names.push_back(k->name);
  }
  if (any_named && names.empty()) throw std::invalid_argument("ask for at least one file format");
  return names;  // (none named: the editor's default)
}

HttpResponse start_render(Editor& ed, const ApiCall& c) {
  Editor::RenderRequest req;
  req.formats = requested_formats(c.body);
  const Json& frames = field(c.body, "frames");
  if (!frames.is_null()) {
    if (!frames.is_array() || frames.size() != 2 || !frames[0].is_number_integer() ||
        !frames[1].is_number_integer())
      throw std::invalid_argument("'frames' is [first, last]");
    req.frames = std::pair{frames[0].get<int>(), frames[1].get<int>()};
  }
  if (auto why = ed.start_render(req)) return error_response(409, *why);  // (one is running)
  return json_response(200, ed.render_status());
}

HttpResponse render_status(Editor& ed, const ApiCall&) {
  return json_response(200, ed.render_status());
}

HttpResponse cancel_render(Editor& ed, const ApiCall&) {
  if (!ed.cancel_render()) return error_response(409, "no render is running");
  return json_response(200, ed.render_status());
}

// A finished render's file, by the extension the path ends in.
HttpResponse render_result(Editor& ed, const ApiCall& c) {
  const std::string ext = c.q.path.substr(c.q.path.rfind('.') + 1);
  std::optional<int> frame;
  if (c.q.query.count("frame")) frame = int(std::clamp(query_number(c.q, "frame", 0), -1e9, 1e9));
  const auto file = ed.render_result(ext, frame);
  if (!file) return error_response(404, "no finished render with a " + ext + " file");
  HttpResponse r;
  r.content_type = sink_kind(*file).media_type;
  r.file = *file;
  r.headers.emplace_back("Content-Disposition",
                         "attachment; filename=\"" + file->filename().string() + "\"");
  return r;
}

// The goals' entries as TOML text of an array of tables ("free" may list bare keys).
std::string goals_toml(const Json& list, const char* name, bool keys) {
  if (!list.is_array() || list.empty())
    throw std::invalid_argument(std::string("'") + name + "' is a non-empty list");
  Json entries = Json::array();
  for (const Json& e : list) {
    if (keys && e.is_string())
      entries.push_back({{"key", e}});
    else if (e.is_object())
      entries.push_back(e);
    else
      throw std::invalid_argument(std::string("each of '") + name + "' is a table" +
                                  (keys ? " or a key" : ""));
  }
  return toml_text(entries);
}

Json solve_report_json(const solve::SolveReport& r) {
  Json values = Json::array(), constraints = Json::array();
  for (const solve::ValueReport& v : r.values)
    values.push_back({{"name", v.name},
                      {"start", v.start},
                      {"value", v.value},
                      {"lo", v.lo},
                      {"hi", v.hi},
                      {"at_bound", v.at_bound}});
  for (const solve::ConstraintReport& c : r.constraints)  // (residual null: not seen)
    constraints.push_back({{"where", c.where},
                           {"kind", c.kind},
                           {"unit", c.unit},
                           {"residual", std::isfinite(c.residual) ? Json(c.residual) : Json()},
                           {"tolerance", c.tolerance},
                           {"met", c.met}});
  return {{"values", values},
          {"constraints", constraints},
          {"iterations", r.iterations},
          {"termination", r.termination},
          {"met", r.all_met()}};
}

// The camera solved for the page's goals (Editor::solve): {"version", "constraints": [...],
// "free": [...], "iterations"?, "apply"?} -> the report, the solve's time, and with "apply" the
// new version and state.
HttpResponse solve(Editor& ed, const ApiCall& c) {
  if (!field(c.body, "version").is_number_integer())
    throw std::invalid_argument("a solve names the document's \"version\"");
  Editor::SolveRequest req;
  req.version = field(c.body, "version").get<int64_t>();
  req.constraints = goals_toml(field(c.body, "constraints"), "constraints", false);
  req.free = goals_toml(field(c.body, "free"), "free", true);
  if (c.body.contains("iterations"))
    req.max_iterations = int(number_in(c.body, "iterations", 1, 1000));
  req.apply = field(c.body, "apply").is_boolean() && field(c.body, "apply").get<bool>();
  const Editor::SolveOutcome o = ed.solve(req);
  if (o.edit.error) return outcome_response(o.edit, ed);
  Json j = solve_report_json(o.report);
  j["ms"] = o.seconds * 1e3;
  j["version"] = o.edit.version;
  if (req.apply) j["state"] = ed.state();
  return json_response(200, j);
}

struct Route {
  const char* method;  // "GET", "POST", or "" for either
  const char* path;
  Handler handle;
};

constexpr Route kRoutes[] = {
    {"GET", "/api/declarations", declarations},
    {"GET", "/api/state", state},
    {"POST", "/api/edit", edit},
    {"POST", "/api/undo", undo},
    {"POST", "/api/redo", redo},
    {"POST", "/api/time", set_time},
    {"GET", "/api/frame", frame},
    {"", "/api/preview", preview},
    {"POST", "/api/pick", pick},
    {"POST", "/api/project", project},
    {"GET", "/api/coins", coins},
    {"GET", "/api/magnification", magnification},
    {"GET", "/api/rays", rays},
    {"POST", "/api/solve", solve},
    {"POST", "/api/save", save},
    {"POST", "/api/render", start_render},
    {"GET", "/api/render", render_status},
    {"POST", "/api/render/cancel", cancel_render},
    {"GET", "/api/render/result.*", render_result},  // (* any extension)
};

bool matches(const Route& r, const std::string& path) {
  const std::string_view p = r.path;
  if (p.ends_with('*')) return path.starts_with(p.substr(0, p.size() - 1));
  return path == p;
}

}  // namespace

HttpResponse Api::route_api(const HttpRequest& q, const std::function<bool()>& client_gone) {
  const bool get = q.method == "GET", post = q.method == "POST";
  if (!get && !post) return error_response(405, "the API takes GET and POST");
  if (const std::string e = json_nesting_error(q.body); !e.empty())
    throw std::invalid_argument("the body is " + e);
  const Json body = post && !q.body.empty() ? Json::parse(q.body) : Json::object();
  if (!body.is_object()) throw std::invalid_argument("the body must be a JSON object");
  for (const Route& r : kRoutes)
    if (matches(r, q.path) && (!*r.method || q.method == r.method))
      return r.handle(editor_, {q, body, client_gone});
  return error_response(404, "no such API call: " + q.method + " " + q.path);
}

}  // namespace anamorph::server
