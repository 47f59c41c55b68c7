// The header rules every request meets before a handler sees it. A header whose meaning a second
// copy would change (Host, Origin, Cookie, the token, Content-Length, ...) may appear once: with
// two, the server and a proxy or browser in front of it could each act on a different one (the
// handler saw only the last). Host must be there and not empty (RFC 9112, 3.2). A request body
// comes with a Content-Length or as chunks, nothing else. Other repeated headers are lists and
// are joined with ", " (RFC 9110, 5.3).
#pragma once

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace anamorph::server {

// `fields` as they arrived (names in any case). The headers by lower-case name, or the reason the
// request is refused (400).
std::optional<std::string> check_headers(
    const std::vector<std::pair<std::string, std::string>>& fields,
    std::map<std::string, std::string>* headers);

}  // namespace anamorph::server
