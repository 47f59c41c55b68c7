#include "server/api_json.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <stdexcept>

namespace anamorph::server {

HttpResponse json_response(int status, const Json& j) {
  HttpResponse r;
  r.status = status;
  // (A message may quote the request's bytes, which need not be UTF-8: replaced, not thrown.)
  r.body = j.dump(-1, ' ', false, Json::error_handler_t::replace);
  return r;
}

HttpResponse error_response(int status, const std::string& message, const std::string& key) {
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

}  // namespace anamorph::server
