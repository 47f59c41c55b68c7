// Saving the editor's document as text: the scene file's own text with the edits spliced in
// where they fit, so its comments, key order and layout stay; when an edit cannot be placed that
// way (a new sub-table inside an array entry, a removed array entry, a table written with dotted
// keys, ...), the whole tree as toml++ writes it. The result always reads back as the document.
#pragma once

#include <string>

#include <toml++/toml.h>

namespace anamorph::server {

struct SavedText {
  std::string text;
  bool normalized = false;  // written whole by toml++ (comments and layout not kept)
  // False when not even the whole rewrite reads back as the document (toml++ cannot write some
  // keys, e.g. with control characters, so that they read back): such a text must not be saved.
  bool reads_back = true;
};

// `original_text` is the file as it was read; `current` the document now.
SavedText saved_text(const std::string& original_text, const toml::table& current);

// The whole tree as toml++ writes it, floats in their shortest form (the fallback above).
std::string normalized_text(const toml::table& t);

}  // namespace anamorph::server
