// The API's JSON and query helpers: responses, errors, a request's fields and query values
// checked (a bad one throws std::invalid_argument, which the API answers with 400 and its text).
#pragma once

#include <cstdint>
#include <string>

#include "math/vec.h"
#include "server/editor.h"
#include "server/http_server.h"

namespace anamorph::server {

HttpResponse json_response(int status, const Json& j);
// {"error": message, "key": key (when there is one)} with `status`.
HttpResponse error_response(int status, const std::string& message, const std::string& key = {});
// A JSON value as TOML text (the scene reader then checks it against the key's declaration).
std::string toml_text(const Json& v);
// body[name], or null when absent.
const Json& field(const Json& body, const char* name);
// body[name] as a number in [lo, hi].
double number_in(const Json& body, const char* name, double lo, double hi);
Json vec3_json(const Vec3& v);
// ?name= as a finite number, all of its text ("12abc" is not 12), or `fallback` when absent.
double query_number(const HttpRequest& q, const char* name, double fallback);
// ?name= as a whole number in [lo, hi].
int64_t query_integer(const HttpRequest& q, const char* name, int64_t fallback, int64_t lo,
                      int64_t hi);
int64_t query_version(const HttpRequest& q);
// The outcome with the document's state after it (the page needs no second request).
HttpResponse outcome_response(const EditOutcome& o, const Editor& editor);

}  // namespace anamorph::server
