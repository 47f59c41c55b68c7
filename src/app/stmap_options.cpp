#include "app/stmap_options.h"

#include <fmt/format.h>

#include <cstdio>

#include "app/common.h"
#include "camera/stmap.h"
#include "params/params.h"

namespace anamorph::app {

std::string source_option_help() {
  std::string s = "Source projection, the input's layout (looking along -z, y up).";
  for (const SourceProjectionInfo* i : source_projections())
    s += fmt::format(" {}: {}", i->usage, i->doc);
  return s;
}

std::unique_ptr<SourceProjection> parse_source(const std::string& spec, double aspect) {
  return make_source_projection(spec, aspect);
}

std::pair<int, int> parse_size(const std::string& option, const std::string& text) {
  int w = 0, h = 0, end = 0;
  if (std::sscanf(text.c_str(), "%dx%d%n", &w, &h, &end) != 2 || size_t(end) != text.size() ||
      w < 1 || h < 1 || w > 65536 || h > 65536)
    throw ParamError(option, fmt::format("{} {}: expected WxH, each in [1, 65536]", option, text));
  return {w, h};
}

int guard_stmap_errors(const std::function<int()>& body) {
  try {
    return body();
  } catch (const ParamError& e) {
    print_error(e.what());
    return kBadInput;
  } catch (const NonCentralCamera& e) {
    print_error(e.what());
    return kBadInput;
  }
}

}  // namespace anamorph::app
