// What `anamorph stmap` and `anamorph warp` share: the --source option and their bad-input
// errors (exit 2).
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <utility>

#include "camera/source_projection.h"

namespace anamorph::app {

// --source's help text, listing every registered kind.
std::string source_option_help();
// make_source_projection (aspect: the image's width / height); ParamError on a bad spec
// (guard_stmap_errors makes it exit 2).
std::unique_ptr<SourceProjection> parse_source(const std::string& spec, double aspect);
// "WxH", both in [1, 65536]; ParamError naming `option` otherwise.
std::pair<int, int> parse_size(const std::string& option, const std::string& text);
// Runs `body`; a bad --source, size or a non-central camera is an error message and exit 2.
int guard_stmap_errors(const std::function<int()>& body);

}  // namespace anamorph::app
