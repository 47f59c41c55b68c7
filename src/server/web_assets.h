// The editor's page (web/: HTML, JavaScript, CSS), built into the binary by CMake
// (web_assets.cmake), so `anamorph serve` needs no files beside it and no network.
#pragma once

#include <string_view>

namespace anamorph::server {

struct WebAsset {
  std::string_view path;  // "/index.html", "/app.js", ...
  std::string_view content_type;
  std::string_view bytes;
};

// The asset at `path`, or null.
const WebAsset* find_web_asset(std::string_view path);

}  // namespace anamorph::server
