#include "server/http_headers.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <string_view>

namespace anamorph::server {

namespace {

// (lower case)
constexpr std::array<std::string_view, 10> kOnce = {
    "host",         "origin",        "cookie",  "x-anamorph-token",  "content-length",
    "content-type", "authorization", "referer", "transfer-encoding", "proxy-authorization"};

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string trimmed(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t"), e = s.find_last_not_of(" \t");
  return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

}  // namespace

std::optional<std::string> check_headers(
    const std::vector<std::pair<std::string, std::string>>& fields,
    std::map<std::string, std::string>* headers) {
  headers->clear();
  for (const auto& [name, value] : fields) {
    const std::string key = lower(name);
    const auto [it, inserted] = headers->emplace(key, value);
    if (inserted) continue;
    if (std::find(kOnce.begin(), kOnce.end(), key) != kOnce.end())
      return "the request has two " + name + " headers (it may have one)";
    it->second += ", " + value;
  }
  const auto host = headers->find("host");
  if (host == headers->end() || trimmed(host->second).empty())
    return "the request has no Host header, or an empty one";
  const auto te = headers->find("transfer-encoding");
  if (te != headers->end() && lower(trimmed(te->second)) != "chunked")
    return "Transfer-Encoding '" + te->second +
           "' is not supported (send chunked, or a "
           "Content-Length)";
  return std::nullopt;
}

}  // namespace anamorph::server
