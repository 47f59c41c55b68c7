// The printf patterns that name a frame sequence's files (`render --frames A:B -o out_%04d.png`,
// and --checkpoint and --stats with --frames): exactly one frame-number conversion %d, with an
// optional field width (%4d, %04d) of at most kMaxFrameWidth, and %% for a percent sign. A
// pattern is checked before anything is formatted: `out_%0999999999d.png` would make a name of a
// billion characters (6.9 GB allocated before the file system refused it).
#pragma once

#include <optional>
#include <string>

namespace anamorph::app {

inline constexpr int kMaxFrameWidth = 64;

// Why `pattern` is not such a pattern (a sentence), or none.
std::optional<std::string> frame_pattern_error(const std::string& pattern);

// --frames: "A:B" or "A" (integers, possibly negative, within +-1e9) into first and last.
bool parse_frame_range(const std::string& text, int* first, int* last);

}  // namespace anamorph::app
