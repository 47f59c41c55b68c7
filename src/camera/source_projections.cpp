// The one list of source projection kinds (adding a kind = one file and one line in kSources).
#include <fmt/format.h>

#include <cmath>
#include <cstdlib>

#include "camera/source_projection.h"
#include "params/params.h"

namespace anamorph {

namespace {
const SourceProjectionInfo* const kSources[] = {&kEquirectSource, &kCubemapSource, &kFisheyeSource,
                                                &kPerspectiveSource};

std::string usages() {
  std::string s;
  for (const SourceProjectionInfo* i : kSources)
    s += (s.empty() ? "" : ", ") + std::string(i->usage);
  return s;
}
}  // namespace

std::span<const SourceProjectionInfo* const> source_projections() { return kSources; }

std::unique_ptr<SourceProjection> make_source_projection(std::string_view spec, double aspect) {
  std::vector<std::string> parts;
  for (size_t at = 0;;) {
    const size_t colon = spec.find(':', at);
    parts.emplace_back(spec.substr(at, colon == std::string_view::npos ? colon : colon - at));
    if (colon == std::string_view::npos) break;
    at = colon + 1;
  }
  for (const SourceProjectionInfo* i : kSources)
    if (parts[0] == i->name) return i->create(std::span(parts).subspan(1), aspect);
  throw ParamError("--source", fmt::format("--source {}: unknown projection \"{}\" (valid: {})",
                                           spec, parts[0], usages()));
}

double source_number(const std::string& text, std::string_view what, double lo, double hi) {
  char* end = nullptr;
  const double x = text.empty() ? NAN : std::strtod(text.c_str(), &end);
  if (!std::isfinite(x) || (end && *end) || x < lo || x > hi)
    throw ParamError("--source", fmt::format("--source: {} \"{}\" must be a number in [{}, {}]",
                                             what, text, lo, hi));
  return x;
}

FovAspect source_fov_aspect(std::span<const std::string> args, std::string_view kind,
                            double max_fov, double example_fov, double image_aspect) {
  if (args.empty() || args.size() > 2)
    throw ParamError("--source", fmt::format("--source {0} needs {0}:FOV[:ASPECT], e.g. {0}:{1}",
                                             kind, example_fov));
  const double fov = source_number(args[0], fmt::format("{} FOV (degrees)", kind), 1e-3, max_fov);
  const double aspect = args.size() > 1
                            ? source_number(args[1], fmt::format("{} ASPECT", kind), 1e-3, 1e3)
                            : image_aspect;
  return {fov, aspect};
}

}  // namespace anamorph
