// Editing a scene's TOML tree by dotted keys: what `--set` overrides, [[animate]] keys and the
// editor's edits have in common. Numeric parts index arrays (arrays of tables and plain arrays
// alike): camera.coin.0.strength, camera.org.points.1.2.
#pragma once

#include <string>
#include <string_view>

#include <toml++/toml.h>

#include "scene/toml_reader.h"

namespace anamorph {

// A value as TOML text in a one-key table { v = ... }; text that is not TOML (a bare word) is
// taken as a string. A value nested deeper than kMaxNesting is a SceneError naming `key`.
toml::table parse_value_text(const std::string& text, const std::string& key = {});

// `key` for a message: as it is, or its start and length when it is long (a key of 50,000
// parts).
std::string shown_key(const std::string& key);

// Whether `s` is well-formed UTF-8 (what TOML text must be; a value that is not cannot be
// written back to a scene file).
bool valid_utf8(std::string_view s);

// Sets the value at `key`, creating tables on the way; an index must name an existing entry.
// Errors are SceneErrors at `where` naming `key` (a key of more than kMaxNesting parts is one).
void set_path(toml::table& root, const std::string& key, const toml::node& value,
              const SourceLoc& where);

// Removes the key or array entry at `key`; false when there was none.
bool remove_path(toml::table& root, const std::string& key);

}  // namespace anamorph
